#pragma once
// All options of the tracker, loaded from one YAML config (config/euroc.yaml documents every
// key). Calibration comes from the config or from EuRoC sensor.yaml files it names.
#include <string>

#include "common/calib/camera_calib.h"
#include "common/config/channels.h"
#include "common/imu/imu_options.h"
#include "tracker/descriptor_match.h"
#include "tracker/direct_options.h"
#include "tracker/imu_buffer.h"
#include "tracker/keyframe_policy.h"
#include "tracker/local_map.h"
#include "tracker/orb_extractor.h"
#include "tracker/pose_opt_types.h"
#include "tracker/stereo_matcher.h"

namespace hs {

// hybrid: ORB only at keyframes, direct tracking in between (the paper). every-frame: ORB and
// descriptor matching on every frame, like ORB-SLAM3's tracking (the Table 4 baseline).
enum class DescriptorMode { kHybrid, kEveryFrame };

struct TrackerOptions {
  StereoCalib calib = euroc_stereo_calib();
  bool stereo = true;  // false: a mono rig (cam0 only)
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
  int reloc_min_inliers = 25;
  int64_t reinit_after_lost_ns = 500'000'000;      // then start a new local map in place
  int64_t max_camera_imu_offset_ns = 200'000'000;  // frame vs newest IMU sample
  int64_t static_init_window_ns = 1'000'000'000;

  ChannelNames channels;
};

// Reads a tracker config. Unknown keys, wrong types or bad values: InputError with file:line.
TrackerOptions load_tracker_options(const std::string& path);

}  // namespace hs
