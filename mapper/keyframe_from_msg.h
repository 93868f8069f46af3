#pragma once
// KEYFRAME message -> MapperKeyframe, validating everything a sender (or a corrupt stream)
// could get wrong. Errors are InputError naming `source` (the channel) and the keyframe id.
#include <string>

#include "hsslam/keyframe_t.hpp"
#include "hsslam/reloc_request_t.hpp"
#include "mapper/mapper_keyframe.h"

namespace hs {

// Checks: t_ns equals pose.t_ns; prev_keyframe_id is -1 or in [0, id); finite pose with a unit
// quaternion; counts match the arrays; 32-byte descriptors; finite keypoints with depth and
// right pixel either (-1, -1) or valid, octave >= 0; every referenced point id is in `points`
// exactly once and observed by exactly one keypoint; finite IMU samples in strictly increasing
// time, all but the last (the interpolation bracket) before t_ns. The IMU lower bound (the previous
// keyframe's time) is not in the message: KeyframeGraph checks it when linking the chain.
MapperKeyframe keyframe_from_msg(const hsslam::keyframe_t& msg, const std::string& source);

// RELOC_REQUEST: the frame as keyframe_from_msg checks it, and next_map_id >= 0 and not the
// frame's own map id.
struct RelocRequest {
  int64_t seq = 0;
  int32_t next_map_id = 0;
  MapperKeyframe frame;
};
RelocRequest reloc_request_from_msg(const hsslam::reloc_request_t& msg, const std::string& source);

}  // namespace hs
