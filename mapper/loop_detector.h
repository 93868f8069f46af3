#pragma once
// Loop detection (issue 7): each new keyframe queries the place index for older keyframes of its
// world that share no points with it, verifies the best candidates geometrically, and accepts a
// loop only when
// - the correction it implies for the query (the drift) is plausible for the path travelled
//   since the candidate: a look-alike place elsewhere (repeated facades, poles every 12 m)
//   implies a jump of the structure's spacing, far beyond what the odometry drifts;
// - it keeps roll and pitch: gravity is observed, only position and yaw drift;
// - the candidate's neighbourhood agrees: the map points of the candidate and its most
//   covisible keyframes, placed in the query's image by the measured pose, are found there by
//   descriptor. A ground texture that repeats every few metres can fool the two keyframes'
//   matching alone (the same tiles one period further on), not the facades and poles around;
// - the next keyframe's loop implies the same correction (consecutive, consistent detections).
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "common/calib/camera_calib.h"
#include "mapper/keyframe_graph.h"
#include "mapper/place_index.h"
#include "mapper/place_verify.h"

namespace hs {

struct LoopDetectionOptions {
  bool enabled = true;
  // Candidates from other worlds (an earlier map of this run, a loaded one): a verified match
  // there merges the two. A loaded map's frame is anywhere: no bound on the move. A world of
  // this run was started in place by the tracker, at its IMU-carried estimate after a loss, so
  // its frame is the older world's but for that drift: a merge must move it less than this. (The
  // blackout scenario: a 90 deg look-alike of the room verified and was consistent.)
  bool merge_worlds = true;
  double merge_in_run_m = 1.0;
  double merge_in_run_rad = 10.0 * M_PI / 180.0;
  PlaceIndexOptions index;
  PlaceVerifyOptions verify;
  size_t candidates = 3;   // best-scoring keyframes verified per query
  double min_age_s = 5.0;  // candidates at least this much older than the query
  // Plausible drift since the candidate: base + per metre of path travelled.
  double drift_base_m = 0.3;
  double drift_per_m = 0.03;
  double drift_base_rad = 3.0 * M_PI / 180.0;
  double drift_rad_per_m = 0.03 * M_PI / 180.0;
  double max_tilt_rad = 2.0 * M_PI / 180.0;  // roll/pitch part of the implied correction
  size_t neighbourhood_keyframes = 5;        // the candidate's most covisible, for the map check
  double neighbourhood_radius_px = 6.0;
  double min_neighbourhood_share = 0.15;  // of its points projecting into the query's image
  int consistent = 2;                     // consecutive keyframes whose loops agree
  double consistency_m = 0.1;
  double consistency_rad = 1.0 * M_PI / 180.0;
};

struct LoopFound {
  int64_t query = -1, candidate = -1;  // keyframe ids
  int64_t query_t_ns = 0, candidate_t_ns = 0;
  Eigen::Isometry3d T_c_q = Eigen::Isometry3d::Identity();  // measured, query body -> candidate
  // World correction it implies: the query's pose should be T_w_q_new = drift * T_w_q.
  Eigen::Isometry3d drift = Eigen::Isometry3d::Identity();
  int inliers = 0;
  double path_m = 0.0;  // travelled from the candidate to the query
  // The candidate is of another world: `drift` moves the query's whole world onto it.
  bool merge = false;
};

// Where the atlas places a lost tracker's frame.
struct PlaceFix {
  int64_t keyframe = -1;                                    // matched
  Eigen::Isometry3d T_w_b = Eigen::Isometry3d::Identity();  // the frame's, in its world
  int inliers = 0;
};

// What one query did (for counters and messages).
struct LoopQueryStats {
  int candidates = 0;    // from the index
  int verified = 0;      // passed geometric verification
  int implausible = 0;   // verified, but an implausible drift or tilt
  int unconfirmed = 0;   // verified, but the candidate's neighbourhood disagrees
  double time_ms = 0.0;  // index query + verification
  std::string message;   // why a verified place was not taken, or the loop
};

class LoopDetector {
 public:
  LoopDetector(const StereoCalib& calib, const LoopDetectionOptions& options);

  // `query` must be in the graph with its current (bundle-adjusted) state. It joins the index
  // unless told not to (localisation only: the map does not grow).
  std::optional<LoopFound> detect(const KeyframeGraph& graph, int64_t query, LoopQueryStats* stats,
                                  bool join_index = true);
  // A lost tracker's frame, not in the graph: the index's best keyframes of any world verified
  // as for a loop, the candidate's neighbourhood found in the frame, roll and pitch kept. A
  // candidate in world `guess_world` (the one the tracker was lost in) must place the frame
  // within merge_in_run_* of its pose, the tracker's IMU-carried guess: a look-alike of the
  // place implies a jump of the structure's spacing. No streak: the tracker is waiting.
  std::optional<PlaceFix> relocalise(const KeyframeGraph& graph, const MapperKeyframe& frame,
                                     std::optional<int32_t> guess_world,
                                     LoopQueryStats* stats) const;
  // A loaded map's keyframe joining the index without a query.
  void add(const KeyframeGraph& graph, int64_t id) {
    path_at(graph, id);
    foreign_.insert(id);
    index_.add(id, graph.keyframe(id)->descriptors);
  }
  // A keyframe leaving the graph (culled).
  void remove(int64_t keyframe_id) {
    index_.remove(keyframe_id);
    path_m_.erase(keyframe_id);
    foreign_.erase(keyframe_id);
  }
  const PlaceIndex& index() const { return index_; }

 private:
  // Path length from the start of the keyframe's world to it, along the keyframes in arrival
  // order (fixed when first asked: the query's, before any correction moves it).
  double path_at(const KeyframeGraph& graph, int64_t id);
  // Share of the neighbourhood's map points that project into the query's image (placed by
  // T_c_q) and are matched there; `projected` is their number.
  double neighbourhood_share(const KeyframeGraph& graph, const MapperKeyframe& query,
                             const MapperKeyframe& candidate, const Eigen::Isometry3d& T_c_q,
                             int* projected) const;
  // Its share is at least min_neighbourhood_share (said in st.message, else counted unconfirmed).
  bool neighbourhood_agrees(const KeyframeGraph& graph, const MapperKeyframe& query,
                            const MapperKeyframe& candidate, const Eigen::Isometry3d& T_c_q,
                            LoopQueryStats& st) const;

  struct WorldPath {
    double length_m = 0.0;
    std::optional<Eigen::Vector3d> last;
  };

  StereoCalib calib_;
  LoopDetectionOptions options_;
  PlaceIndex index_;
  std::unordered_map<int64_t, double> path_m_;
  std::unordered_set<int64_t> foreign_;  // loaded keyframes
  std::unordered_map<int32_t, WorldPath> world_path_;
  std::optional<LoopFound> streak_;  // the previous keyframe's plausible loop
  int streak_length_ = 0;
};

}  // namespace hs
