#pragma once
// The back end's local mapping (paper Fig. 4, as ORB-SLAM3's local mapping): each keyframe from
// the tracker joins the keyframe graph, a local visual-inertial bundle adjustment runs over its
// covisible window, points that fail it are removed, redundant keyframes are culled, and the
// refined window goes back to the tracker as a MapCorrection. Single-threaded and
// deterministic; the hs-mapper process and hs-run --with-mapper drive it.
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_set>

#include "common/calib/camera_calib.h"
#include "common/core/map_correction.h"
#include "mapper/keyframe_culling.h"
#include "mapper/keyframe_graph.h"
#include "mapper/local_ba.h"
#include "mapper/window_input.h"

namespace hs {

struct MapperOptions {
  KeyframeGraphOptions graph;
  WindowInputOptions window;
  LocalBaOptions ba;
  CullingOptions culling;
  bool cull_keyframes = true;
  // IMU refinement: every local BA also estimates the gravity direction in the tracker's world
  // (levelled at start with a biased accelerometer) with a prior of this sigma around the
  // previous estimate, so it settles as the motion makes it observable and stays where it is
  // while the body rests. 0 holds gravity at the world's -z. Measured on room_mav (20 s):
  // ATE 3.8 mm held, 2.9 mm estimated; steps of 0.05-0.1 deg converge too slowly.
  double gravity_step_sigma_rad = 0.5 * M_PI / 180.0;

  // A point is removed when at least this share of its observations in the window (and at
  // least two) fail the bundle adjustment's chi2 test.
  double point_outlier_ratio = 0.5;
};

// Cumulative.
struct MapperCounters {
  int64_t keyframes = 0;  // accepted into the graph
  int64_t local_ba_runs = 0;
  int64_t culled_keyframes = 0;
  int64_t removed_points = 0;
  // Keypoints of later keyframes still naming a removed point (sent before the tracker applied
  // the removal): the association is dropped, the point stays removed.
  int64_t removed_point_observations = 0;
  int64_t imu_factors_skipped = 0;  // keyframe intervals with an IMU gap
};

struct MapperStep {
  std::optional<MapCorrection> correction;  // none for a duplicate keyframe
  LocalBaStats ba;
  int window_keyframes = 0;
  int window_points = 0;
  std::string message;  // what was dropped and why, if anything
};

class Mapper {
 public:
  Mapper(const StereoCalib& calib, const MapperOptions& options);

  MapperStep add_keyframe(MapperKeyframe keyframe);

  const KeyframeGraph& graph() const { return graph_; }
  const MapperCounters& counters() const { return counters_; }
  // Gravity in the tracker's world frame as estimated so far.
  const Eigen::Vector3d& gravity_w() const { return g_w_; }

 private:
  StereoCalib calib_;
  MapperOptions options_;
  KeyframeGraph graph_;
  LocalBundleAdjuster ba_;
  MapperCounters counters_;
  Eigen::Vector3d g_w_ = default_gravity_w();
  std::unordered_set<int64_t> removed_points_;
  int64_t next_seq_ = 0;
};

}  // namespace hs
