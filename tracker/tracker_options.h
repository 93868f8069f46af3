#pragma once
// All options of the tracker, loaded from one YAML config (config/euroc.yaml documents every
// key). Calibration comes from the config or from EuRoC sensor.yaml files it names.
#include <cmath>
#include <string>

#include "common/calib/camera_calib.h"
#include "common/config/channels.h"
#include "common/features/descriptor_match.h"
#include "common/features/epipolar_points.h"
#include "common/imu/imu_options.h"
#include "common/imu/vi_alignment.h"
#include "tracker/direct_options.h"
#include "tracker/imu_buffer.h"
#include "tracker/keyframe_policy.h"
#include "tracker/local_map.h"
#include "tracker/mono_initialiser.h"
#include "tracker/node/node_options.h"
#include "tracker/orb_extractor.h"
#include "tracker/pose_opt_types.h"
#include "tracker/stereo_matcher.h"

namespace hs {

// hybrid: ORB only at keyframes, direct tracking in between (the paper). every-frame: ORB and
// descriptor matching on every frame, like ORB-SLAM3's tracking (the Table 4 baseline).
enum class DescriptorMode { kHybrid, kEveryFrame };

// A relocalisation must agree with the IMU prediction while the IMU has carried the state
// for at most trust_imu_ns: within position_m + accel_error_mps2 * dt^2 / 2 and rotation_rad.
struct RelocGateOptions {
  double position_m = 0.3;
  double accel_error_mps2 = 0.5;
  double rotation_rad = 0.2;
  int64_t trust_imu_ns = 5'000'000'000;
};

// Mapper corrections (MAP_UPDATE) move the current pose with the newest corrected keyframe.
// A larger move is a jump a POSE consumer must be told of: the map id changes.
// The mapper's gravity is adopted when it is this close to the world's -z and to 9.81 m/s^2:
// a world levelled at rest is off by the accelerometer bias (0.1 m/s^2 is 0.6 deg), more is
// a broken mapper.
struct CorrectionOptions {
  double max_silent_translation_m = 0.02;
  double max_silent_rotation_rad = 0.5 * M_PI / 180.0;
  double max_gravity_tilt_rad = 5.0 * M_PI / 180.0;
  double max_gravity_magnitude_error = 0.05;  // relative
};

// A mono rig (issue 10): the two-view start, then vision alone until the IMU gives scale and
// gravity (align_visual_inertial_up_to_scale), new points at keyframes by epipolar matching
// with the previous keyframe.
struct MonoOptions {
  MonoInitOptions init;
  // The two-view map's scale until the IMU fixes it: its median depth is set to this guess,
  // so that metric thresholds (keyframe pose change) are about right in between.
  double initial_median_depth_m = 3.0;
  // Alignment is first tried once the window spans vi_alignment_window_ns; a refused window
  // grows to this span, then slides.
  int64_t max_alignment_window_ns = 4'000'000'000;
  // Poses of a window at least this far apart go into the alignment (the IMU in between).
  int64_t alignment_spacing_ns = 200'000'000;
  // The accel bias is always estimated, under a prior of 0.2 m/s^2 (a MEMS IMU's range) when the
  // window alone cannot separate it from a gravity tilt: held at a wrong value it turns into a
  // scale error (room_mav: 0.1 m/s^2 made 10-20%; real V1_01 flight: Sim(3) scale error 22%
  // held, 14% with the prior). The vision's attitudes may drift 1 deg/s: a mono odometry's
  // pitch drifted 0.75 deg/s on the real V1_01 flight, and taken for gyro bias it made the
  // scale 14.6% off there, 3.7% with the allowance.
  ViAlignmentOptions alignment = [] {
    ViAlignmentOptions o;
    o.max_accel_bias_sigma = 0.05;
    o.accel_bias_prior_sigma = 0.2;
    o.vision_rotation_drift_sigma = 1.0 * M_PI / 180.0;
    return o;
  }();
  EpipolarPointOptions points;
  // Once tracking, the map's scale is checked against the IMU over the last refine_window_ns of
  // frames every refine_period_ns, and corrected (about the current camera, so the pose does
  // not jump) when the estimate is this sure: the tracker has no bundle adjustment, and a
  // motion-only pose optimisation cannot change the scale of the points it rests on.
  int64_t refine_window_ns = 4'000'000'000;
  int64_t refine_period_ns = 500'000'000;
  double refine_max_scale_sigma = 0.02;
};

struct TrackerOptions {
  StereoCalib calib = euroc_stereo_calib();
  bool stereo = true;  // false: a mono rig (cam0 only)
  MonoOptions mono;
  ImuOptions imu;
  ImuBufferOptions imu_buffer;
  OrbOptions orb;
  StereoMatchOptions stereo_match;
  DirectOptions direct;
  PoseOptOptions pose_opt;
  KeyframePolicyOptions keyframe;
  LocalMapOptions local_map;
  DescriptorMatchOptions matching;
  DescriptorMode descriptors = DescriptorMode::kHybrid;

  int pyramid_levels = 4;               // the paper's four-layer pyramid
  int max_points_per_frame = 250;       // map points tracked per frame (spread over a grid)
  int point_grid_px = 40;               // one point per cell first, then fill
  double patch_search_radius_px = 4.0;  // after direct alignment
  int init_min_points = 60;             // stereo points needed to start a map
  int max_new_points_per_keyframe = 200;
  int new_point_cell_px = 24;  // new points only in cells without a tracked point
  // A tracked point's patch is re-anchored on each new keyframe (true), or kept on the keyframe
  // that made it until that keyframe leaves the window (false). False tracks with less drift
  // (tracker alone, vehicle_loop 50 s seeds 1-4: ATE 2.84 cm mean against 3.98), but every
  // keyframe's view of a point then carries its one anchor's error, which the mapper takes as
  // independent (room_mav 20 s with the mapper: 0.11 cm against 0.08).
  bool reanchor_every_keyframe = true;
  int reloc_min_inliers = 25;
  int64_t reinit_after_lost_ns = 500'000'000;  // then start a new local map in place
  // ... which continues the map (same map id: the pose was dead-reckoned by the IMU) when
  // tracking was lost for at most this long and the IMU has no gap since the last keyframe (the
  // IMU buffer keeps 5 s). As ORB-SLAM3's "recently lost" window.
  int64_t continue_map_within_ns = 3'000'000'000;
  // A loss the IMU cannot bridge, with a mapper present: the lost frame is sent to the mapper's
  // atlas (RELOC_REQUEST), and a new map starts in place only when no answer placed it within
  // this long of the first request (0: never asks). Found, the tracker continues in the
  // atlas map the answer names.
  int64_t atlas_wait_ns = 500'000'000;
  int64_t max_camera_imu_offset_ns = 200'000'000;  // frame vs newest IMU sample
  int64_t static_init_window_ns = 1'000'000'000;
  // Moving start: visual tracking this long before vision and IMU are aligned.
  int64_t vi_alignment_window_ns = 1'000'000'000;
  // Longer IMU gaps (or IMU behind the camera by more) are not interpolated: vision alone.
  int64_t max_interpolated_imu_gap_ns = 50'000'000;
  RelocGateOptions reloc_gate;
  CorrectionOptions corrections;
  // Scales the previous frame's marginal information before it becomes the next frame's prior.
  // Map points are held fixed, so a chain of priors would count the same map errors again every
  // frame and grow overconfident (measured on room_mav: ATE 3.1 cm at 1.0, 0.5-0.7 cm at
  // 0.5-0.7); s < 1 keeps a memory of about 1 / (1 - s) frames.
  double prior_fading = 0.6;
  // Threads for the parallel steps (per-point patch alignment, the two halves of the ORB
  // pyramid, the stereo pyramids): 0 leaves OpenCV's default (all cores). Process-wide, as
  // OpenCV's thread pool is; results do not depend on it.
  int threads = 0;

  ChannelNames channels;
  NodeOptions node;  // the hs-tracker process (queue, POSE_IMU rate, heartbeat)
};

// Reads a tracker config. Unknown keys, wrong types or bad values: InputError with file:line.
TrackerOptions load_tracker_options(const std::string& path);

}  // namespace hs
