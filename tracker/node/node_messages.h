#pragma once
// The hsslam messages hs-tracker publishes, built from the tracker's results.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "hsslam/keyframe_t.hpp"
#include "hsslam/odometry_t.hpp"
#include "hsslam/reloc_request_t.hpp"
#include "hsslam/tracker_status_t.hpp"
#include "tracker/tracker.h"
#include "tracker/tracker_types.h"

namespace hs {

using NamedCounter = std::pair<std::string, int64_t>;

// The tracker's cumulative counters (frames, rejected input, IMU rejections, ...), by name.
std::vector<NamedCounter> tracker_counters(const TrackerCounters& tracker,
                                           const ImuBufferCounters& imu);

// POSE: the frame's state with its covariance over (rotation, position). Needs a frame with a
// state (accepted and not initialising).
hsslam::odometry_t pose_msg(const FrameResult& r);

hsslam::tracker_status_t status_msg(const FrameResult& r, const std::vector<NamedCounter>& counters,
                                    const std::string& message);

// KEYFRAME: keypoints, descriptors, the map points they observe (positions from `map`; a
// keypoint whose point is no longer in the map is sent unassociated), and the IMU samples since
// the previous keyframe.
hsslam::keyframe_t keyframe_msg(const Keyframe& kf, const LocalMap& map, int32_t map_id);

// RELOC_REQUEST: the lost frame as a keyframe of map `map_id` (the one the tracker was lost in).
hsslam::reloc_request_t reloc_request_msg(const AtlasQuery& q, int32_t map_id);

}  // namespace hs
