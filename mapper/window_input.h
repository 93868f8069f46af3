#pragma once
// The local bundle adjustment problem of one keyframe graph window (mapper/keyframe_graph.h ->
// mapper/local_ba.h): optimised keyframes, the fixed keyframes that also see their points or
// close the IMU chain, every observation of the window's points, and IMU factors between
// consecutive keyframes of the set.
#include <cstdint>
#include <set>
#include <vector>

#include "common/imu/imu_options.h"
#include "mapper/keyframe_graph.h"
#include "mapper/local_ba.h"

namespace hs {

struct WindowInputOptions {
  ImuOptions imu;
  // Keypoint noise at octave 0. Tracked keypoints are sub-pixel (patch alignment): against the
  // simulator's truth their residuals are 0.15 px per axis (mapper/offline/observation_check.h).
  // Measured on room_mav 20 s seeds 1 and 2 (slanted stereo): ATE 0.78 / 0.83 mm at 0.15 px,
  // 1.04 / 0.83 at 0.2, 1.91 / 1.23 at 0.3, 2.42 / 2.06 at 0.6: too large a sigma lets the IMU
  // bend the window. Local BA takes 12.6 iterations instead of 8.6 at 0.3.
  double pixel_sigma = 0.15;
  double octave_scale = 1.2;  // ORB pyramid scale: sigma = pixel_sigma * scale^octave
  // The same for keypoints that arrived without a point (MapperKeypoint::detected): ORB
  // detections, not tracked to sub-pixel, seeing a point the mapper triangulated
  // (mapper/new_points.h) or a revisited one found again (mapper/point_fusion.h).
  double detected_pixel_sigma = 1.0;
  int64_t max_imu_gap_ns = 50'000'000;  // an interval with a longer IMU gap gets no IMU factor
  // Points farther than this from every optimised keyframe are held fixed (0: none). The
  // Mapper sets it from the calibration (MapperOptions::far_point_disparity_px).
  double fixed_point_distance_m = 0.0;
  // ... from every keyframe observing it instead (a full BA, whose keyframes are all optimised).
  bool far_from_observers = false;
};

struct WindowInput {
  LocalBaInput input;
  int imu_factors_skipped = 0;  // intervals whose IMU has a gap
};

// Stereo keypoints (a right pixel known) become two observations, one per camera: the images
// are not rectified, so the right view is a full 2D measurement. Points seen by a single
// keyframe are left out; far points are held fixed (see fixed_point_distance_m).
WindowInput window_input(const KeyframeGraph& graph, const LocalWindow& window,
                         const WindowInputOptions& options);

// IMU factors along the graph's chain between keyframes of `all`, except where both ends are
// in `fixed`; intervals with an IMU gap get none and are counted in `skipped`.
std::vector<BaImuFactor> chain_imu_factors(const KeyframeGraph& graph, const std::set<int64_t>& all,
                                           const std::set<int64_t>& fixed,
                                           const WindowInputOptions& options, int* skipped);

}  // namespace hs
