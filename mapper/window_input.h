#pragma once
// The local bundle adjustment problem of one keyframe graph window (mapper/keyframe_graph.h ->
// mapper/local_ba.h): optimised keyframes, the fixed keyframes that also see their points or
// close the IMU chain, every observation of the window's points, and IMU factors between
// consecutive keyframes of the set.
#include <cstdint>

#include "common/calib/camera_calib.h"
#include "common/imu/imu_options.h"
#include "mapper/keyframe_graph.h"
#include "mapper/local_ba.h"

namespace hs {

struct WindowInputOptions {
  ImuOptions imu;
  // Keypoint noise at octave 0. Tracked keypoints are sub-pixel (patch alignment): their
  // residuals after BA on room_mav are 0.12 px median. Measured there (20 s): ATE 2.8 mm at
  // 0.3 px, 5.2 mm at 0.5, 9.6 mm at 1.0: too large a sigma lets the IMU bend the window.
  double pixel_sigma = 0.3;
  double octave_scale = 1.2;            // ORB pyramid scale: sigma = pixel_sigma * scale^octave
  int64_t max_imu_gap_ns = 50'000'000;  // an interval with a longer IMU gap gets no IMU factor
};

struct WindowInput {
  LocalBaInput input;
  int imu_factors_skipped = 0;  // intervals whose IMU has a gap
};

// Stereo keypoints (u_right and depth known) become two observations. The images are not
// rectified and KEYFRAME carries only the right column, so the right view's row is the
// projection of the keypoint's stereo point into cam1: that row says little about depth, the
// column carries the stereo constraint.
WindowInput window_input(const KeyframeGraph& graph, const LocalWindow& window,
                         const StereoCalib& calib, const WindowInputOptions& options);

}  // namespace hs
