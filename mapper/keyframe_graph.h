#pragma once
// The mapper's keyframe graph and map point store: keyframes, the points they observe,
// covisibility weights (number of shared points), and the tracker's temporal chain for IMU
// factors. Tolerates a lossy, unordered KEYFRAME stream (UDP multicast):
// - a keyframe id seen before (even if since removed) is ignored and counted;
// - a keyframe whose previous keyframe is absent is inserted and counted; its IMU link appears
//   if the previous one arrives late (links are derived from prev ids when queried);
// - worlds: a map id whose first keyframe names no previous keyframe (the tracker started a new
//   map, its frame unrelated to the old) is a world of its own. A map id whose first keyframe
//   continues one in the graph (the tracker stated a jump of its estimate, from a relocalisation
//   or a mapper correction, in the same map) joins that keyframe's world. A keyframe only gains
//   covisibility with keyframes of its own world, windows and fixed sets stay inside it, and the
//   IMU chain never crosses worlds. Point ids are unique across map ids, so a point seen from
//   two worlds is one point with observations from both.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "mapper/mapper_keyframe.h"

namespace hs {

struct KeyframeGraphOptions {
  size_t window_covisible = 10;  // local window: the reference + this many most covisible
  int window_min_shared = 1;     // ... sharing at least this many points with it
  // Keyframes outside the window that see its points are held fixed: the ones seeing the most
  // of them, up to this many (0: all). Each adds its observations to the BA's cost.
  size_t max_fixed_keyframes = 0;
};

// Points the mapper triangulates itself get ids from here up: the tracker's ids stay below, and
// the tracker never hears of these (they refine keyframe poses only).
constexpr int64_t kMapperPointIdBase = int64_t{1} << 60;
inline bool mapper_made_point(int64_t id) {
  return id >= kMapperPointIdBase;
}

struct Observation {
  int64_t keyframe_id = -1;
  int keypoint = -1;  // index into that keyframe's keypoints
};

struct MapperPoint {
  int64_t id = -1;
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();  // owned by the mapper after creation
  std::vector<Observation> observations;
  Descriptor descriptor{};  // the observation's with the least median distance to the others
  int64_t first_keyframe_id = -1;
};

// Problems seen in the input stream.
struct KeyframeGraphCounters {
  int64_t inserted = 0;
  int64_t duplicates = 0;    // id seen before: ignored
  int64_t out_of_order = 0;  // arrived after a keyframe with a larger id
  int64_t missing_prev = 0;  // previous keyframe absent on arrival (lost, late or removed)
  int64_t forks = 0;         // previous keyframe already has a successor: link dropped
  int64_t map_changes = 0;   // map id differs from the previously inserted keyframe's
  int64_t new_worlds = 0;    // map ids that started a world (not continuing one)
};

// Keyframes and points a local bundle adjustment works on (ids ascending).
struct LocalWindow {
  std::vector<int64_t> keyframes;        // optimised: the reference and its covisible set
  std::vector<int64_t> points;           // observed by `keyframes`
  std::vector<int64_t> fixed_keyframes;  // also observe `points`, held fixed
};

class KeyframeGraph {
 public:
  enum class InsertResult { kInserted, kDuplicate };

  explicit KeyframeGraph(const KeyframeGraphOptions& options = {}) : options_(options) {}

  // `kf` must be valid as keyframe_from_msg guarantees. Points unknown to the graph are created
  // at the message's position; known points only gain the observation.
  InsertResult insert(MapperKeyframe kf);
  // Both return false if the id is absent. Removing a keyframe drops points left unobserved
  // and relinks its successor to its predecessor, prepending its IMU samples.
  bool remove_keyframe(int64_t id);
  bool remove_point(int64_t id);
  // A point of the mapper's own at p_w, seen by the given keypoints (each free: point_id -1, of
  // a keyframe of one world). Returns its id (from kMapperPointIdBase up).
  int64_t add_point(const Eigen::Vector3d& p_w, const std::vector<Observation>& observations);
  // A free keypoint (point_id -1) of a keyframe not yet seeing point `id` now sees it.
  void add_observation(int64_t id, const Observation& o);
  // One point found twice (a revisit): `drop`'s observations move to `keep`, except those of
  // keyframes already seeing `keep` (their keypoints are freed), and `drop` is removed.
  // moved_as_detections: the moved keypoints become `detected` (they followed `drop`'s track,
  // off `keep`'s by the difference of the two tracks' first detections).
  void fuse_point(int64_t drop, int64_t keep, bool moved_as_detections = false);
  // Every map id of world `from` joins world `into` (two maps found to be one). Their frames
  // must agree by now: the caller moved one onto the other.
  void merge_world(int32_t from, int32_t into);

  const MapperKeyframe* keyframe(int64_t id) const;
  const MapperPoint* point(int64_t id) const;
  std::vector<int64_t> keyframe_ids() const;  // ascending
  std::vector<int64_t> point_ids() const;     // ascending
  size_t num_keyframes() const { return keyframes_.size(); }
  size_t num_points() const { return points_.size(); }
  const KeyframeGraphCounters& counters() const { return counters_; }

  // Optimised values written back (ids must exist).
  void set_state(int64_t keyframe_id, const NavState& state);
  void set_position(int64_t point_id, const Eigen::Vector3d& p_w);

  int shared_points(int64_t a, int64_t b) const;
  // Up to n keyframes sharing points with `id`, most shared first (ties: newest first).
  std::vector<int64_t> most_covisible(int64_t id, size_t n) const;
  LocalWindow local_window(int64_t id) const;

  // The world (see above) of a keyframe's map id.
  int32_t world(int64_t keyframe_id) const;
  // The world of a map id, if any keyframe of it has arrived (or it was joined to one).
  std::optional<int32_t> world_of_map(int32_t map_id) const;
  // A map id no keyframe has named yet joins `world` (a lost tracker relocalised in it, which
  // continues in that map id). False when the map id is known already.
  bool join_map(int32_t map_id, int32_t world);
  // The previous keyframe if an IMU factor may join the two: it is present, of the same
  // world, and `id` has IMU samples, none but the first before the previous keyframe's time.
  std::optional<int64_t> imu_predecessor(int64_t id) const;
  // The keyframe whose imu_predecessor is `id`, if any.
  std::optional<int64_t> imu_successor(int64_t id) const;

 private:
  struct Node {
    MapperKeyframe kf;
    std::unordered_map<int64_t, int> covisibility;  // other keyframe id -> shared points
  };

  const Node& node(int64_t id) const;
  void add_weight(int64_t a, int64_t b, int delta);
  void update_descriptor(MapperPoint& p) const;

  KeyframeGraphOptions options_;
  std::unordered_map<int64_t, Node> keyframes_;
  std::unordered_map<int64_t, MapperPoint> points_;
  std::unordered_map<int64_t, int64_t> successor_;  // prev id -> the keyframe naming it prev
  std::unordered_set<int64_t> seen_ids_;
  int64_t max_id_ = -1;
  int64_t next_point_id_ = kMapperPointIdBase;
  std::optional<int32_t> last_map_id_;
  std::unordered_map<int32_t, int32_t> world_of_map_;  // map id -> world (the first map id's)
  KeyframeGraphCounters counters_;
};

}  // namespace hs
