#pragma once
// Conversions between the plain structs and the hsslam LCM messages. The *_from_msg functions
// validate everything a sender could get wrong and throw InputError naming `source` (the
// channel) rather than return garbage.
#include <string>
#include <vector>

#include "common/core/map_correction.h"
#include "common/core/reloc_answer.h"
#include "common/core/types.h"
#include "common/dataset/stereo_frame.h"
#include "hsslam/ground_truth_t.hpp"
#include "hsslam/imu_batch_t.hpp"
#include "hsslam/keyframe_pose_t.hpp"
#include "hsslam/map_update_t.hpp"
#include "hsslam/odometry_t.hpp"
#include "hsslam/reloc_answer_t.hpp"
#include "hsslam/stereo_frame_t.hpp"

namespace hs {

enum class ImageEncoding { kMono8, kPng };
// "mono8" or "png"; throws InputError otherwise.
ImageEncoding parse_image_encoding(const std::string& name);

// Images must be CV_8UC1 (any row step); MONO8 rows are packed (stride = width).
hsslam::stereo_frame_t frame_to_msg(const StereoFrame& frame, ImageEncoding encoding);
// Checks: 1 or 2 images of equal size, stride >= width, size = stride * height (MONO8), PNG
// decoding to an 8-bit mono image of the declared size.
StereoFrame frame_from_msg(const hsslam::stereo_frame_t& msg, const std::string& source);

// `samples` must be non-empty and in time order; msg.t_ns is the last sample's time.
hsslam::imu_batch_t imu_batch_to_msg(const std::vector<ImuSample>& samples, int64_t seq);
// Checks: at least one sample, finite values, strictly increasing times, t_ns = last time.
std::vector<ImuSample> imu_batch_from_msg(const hsslam::imu_batch_t& msg,
                                          const std::string& source);

hsslam::ground_truth_t ground_truth_to_msg(const NavState& x);
// Checks: finite values, unit quaternion (to 1e-3; renormalised).
NavState ground_truth_from_msg(const hsslam::ground_truth_t& msg, const std::string& source);

// Covariance is left zero ("unknown"); set msg.covariance after if known.
hsslam::odometry_t odometry_to_msg(const NavState& x, int64_t seq, int32_t map_id, int8_t state,
                                   float quality);
// Checks as for ground truth, plus a known state, quality in [0, 1], finite covariance.
NavState odometry_from_msg(const hsslam::odometry_t& msg, const std::string& source);

hsslam::keyframe_pose_t keyframe_pose_to_msg(int64_t id, const NavState& x);
// Checks as for ground truth, plus id >= 0.
NavState keyframe_pose_from_msg(const hsslam::keyframe_pose_t& msg, const std::string& source);

// A LOCAL_BA update (no rigid correction: identity p/q_new_old, previous_map_id = map_id).
hsslam::map_update_t map_update_to_msg(const MapCorrection& c);
// Checks: kind LOCAL_BA (LOOP, MERGE and FULL_BA are not produced yet: refused by name), counts
// match the arrays, keyframe poses as keyframe_pose_from_msg, finite point positions, no id
// twice in a list, ids >= 0.
MapCorrection map_correction_from_msg(const hsslam::map_update_t& msg, const std::string& source);

// Velocity and biases of the pose are left zero (the tracker keeps its own).
hsslam::reloc_answer_t reloc_answer_to_msg(const RelocAnswer& a);
// Checks: a found answer's pose as keyframe_pose_from_msg and map_id >= 0, inliers >= 0.
RelocAnswer reloc_answer_from_msg(const hsslam::reloc_answer_t& msg, const std::string& source);

}  // namespace hs
