#pragma once
// The tracker's own bounded map: the most recent keyframes and the points they observe, so the
// tracker works with no mapper. Older keyframes leave the window but stay (as image thumbnail +
// descriptors + pose) in a bounded database for relocalisation.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

#include "common/core/types.h"
#include "tracker/image_pyramid.h"
#include "tracker/orb_extractor.h"

namespace hs {

using Descriptor = std::array<uint8_t, 32>;

struct MapPoint {
  int64_t id = -1;
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
  Descriptor descriptor{};
  // Where the point was first seen: its reference keyframe and pixel there (the patch that
  // direct per-point alignment matches against).
  int64_t ref_keyframe_id = -1;
  Eigen::Vector2d ref_uv = Eigen::Vector2d::Zero();
  int octave = 0;
  // Unit normal of the surface at the point (from the stereo match's slant), for the patch's
  // warp; zero when unknown (fronto-parallel).
  Eigen::Vector3d n_w = Eigen::Vector3d::Zero();
  // Mono: the keyframes that saw the point and where (raw pixel), for its triangulation from
  // all of them (a stereo point has its depth from the pair and needs none).
  std::vector<std::pair<int64_t, Eigen::Vector2d>> sightings;
  int times_tracked = 0;  // frames in which the point was an inlier
  int times_missed = 0;   // consecutive frames it was expected but not an inlier
};

struct Keyframe {
  int64_t id = -1;
  NavState state;                  // body state at the keyframe
  Eigen::Isometry3d T_w_c0;        // cam0 pose
  ImagePyramid pyramid;            // cam0; released when the keyframe leaves the window
  cv::Mat thumbnail;               // coarsest pyramid level, kept for global relocalisation (Eq. 8)
  OrbFeatures features;            // cam0 keypoints and descriptors
  std::vector<int64_t> point_ids;  // per keypoint: the map point it observes, -1 if none
  std::vector<Eigen::Vector2f> uv_right;  // per keypoint: raw cam1 pixel, (-1, -1) if none
  std::vector<float> depth;               // per keypoint: depth in cam0, -1 if none
  std::vector<ImuSample> imu;             // samples since the previous keyframe
  // Per keypoint, the observed point's position frozen when the keyframe left the window (its
  // points may leave the map; relocalisation still needs them). Empty while in the window.
  std::vector<Eigen::Vector3d> frozen_p_w;
  int64_t prev_keyframe_id = -1;
};

// A new world frame for a map built before gravity (and, mono, the scale) was known: p_w' =
// scale * R_new_old * p_w + t. Cameras move with the points; a body keeps its metric lever arm
// to its camera, so its state follows the camera's.
struct WorldSimilarity {
  Eigen::Matrix3d R_new_old = Eigen::Matrix3d::Identity();
  double scale = 1.0;
  Eigen::Vector3d t = Eigen::Vector3d::Zero();

  Eigen::Vector3d point(const Eigen::Vector3d& p_w) const { return scale * (R_new_old * p_w) + t; }
  Eigen::Isometry3d camera(const Eigen::Isometry3d& T_w_c) const;
  // Velocity and biases: scaled and rotated, as given.
  NavState body(const NavState& x, const Eigen::Isometry3d& T_b_c) const;
};

struct LocalMapOptions {
  int max_keyframes = 10;            // window of keyframes whose points are tracked
  int max_database_keyframes = 300;  // older keyframes kept for relocalisation
  int max_missed = 10;               // drop a point expected but not tracked this many frames
};

class LocalMap {
 public:
  explicit LocalMap(const LocalMapOptions& options = {}) : options_(options) {}

  int64_t new_point_id() { return next_point_id_++; }
  int64_t new_keyframe_id() { return next_keyframe_id_++; }

  void add_point(const MapPoint& point) { points_[point.id] = point; }
  MapPoint* point(int64_t id);
  const std::unordered_map<int64_t, MapPoint>& points() const { return points_; }
  void remove_point(int64_t id) { points_.erase(id); }

  // Adds a keyframe; the oldest leaves the window (into the database) when over the limit,
  // and points referenced by no window keyframe are dropped.
  void add_keyframe(std::shared_ptr<Keyframe> keyframe);
  const std::deque<std::shared_ptr<Keyframe>>& window() const { return window_; }
  const std::deque<std::shared_ptr<Keyframe>>& database() const { return database_; }
  std::shared_ptr<Keyframe> keyframe(int64_t id) const;
  // Whether keyframe `id` is still in the window (holds its image) once one more is added.
  bool in_window_after_next_keyframe(int64_t id) const;
  std::shared_ptr<Keyframe> latest_keyframe() const {
    return window_.empty() ? nullptr : window_.back();
  }

  // Re-expresses everything in a new world frame: points, keyframe poses and states, frozen
  // positions. Used when the gravity direction (and a mono map's scale) is found after start.
  void transform_world(const WorldSimilarity& S, const Eigen::Isometry3d& T_b_c0);

  void clear();
  // Moves every window keyframe to the database and drops all points (a new local map starts).
  void retire_window();

  // Per keypoint of `kf`: the observed point's position, or nullopt (live map points for window
  // keyframes, frozen positions for database keyframes).
  std::vector<std::optional<Eigen::Vector3d>> point_positions(const Keyframe& kf) const;

 private:
  // The next keyframe added makes the oldest leave the window.
  bool window_full() const { return static_cast<int>(window_.size()) >= options_.max_keyframes; }
  void retire_oldest();
  void drop_unreferenced_points();

  LocalMapOptions options_;
  std::deque<std::shared_ptr<Keyframe>> window_;
  std::deque<std::shared_ptr<Keyframe>> database_;
  std::unordered_map<int64_t, MapPoint> points_;
  int64_t next_point_id_ = 0;
  int64_t next_keyframe_id_ = 0;
};

}  // namespace hs
