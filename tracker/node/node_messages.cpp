#include "tracker/node/node_messages.h"

#include <stdexcept>
#include <unordered_set>

#include "common/lcm/convert.h"

namespace hs {
namespace {

void copy3(const Eigen::Vector3d& v, double* out) {
  for (int i = 0; i < 3; ++i) out[i] = v[i];
}

}  // namespace

std::vector<NamedCounter> tracker_counters(const TrackerCounters& t, const ImuBufferCounters& i) {
  return {{"frames", t.frames},
          {"keyframes", t.keyframes},
          {"rejected_out_of_order", t.rejected_out_of_order},
          {"rejected_bad_image", t.rejected_bad_image},
          {"rejected_clock_offset", t.rejected_clock_offset},
          {"missing_right_image", t.missing_right_image},
          {"imu_gaps", t.imu_gaps},
          {"frames_without_imu", t.frames_without_imu},
          {"lost_frames", t.lost_frames},
          {"relocalisations", t.relocalisations},
          {"relocalisations_rejected", t.relocalisations_rejected},
          {"reinitialisations", t.reinitialisations},
          {"maps_continued", t.maps_continued},
          {"atlas_requests", t.atlas_requests},
          {"atlas_relocalisations", t.atlas_relocalisations},
          {"atlas_answers_ignored", t.atlas_answers_ignored},
          {"scale_corrections", t.scale_corrections},
          {"corrections_applied", t.corrections_applied},
          {"corrections_ignored", t.corrections_ignored},
          {"correction_jumps", t.correction_jumps},
          {"last_correction_lag_ms", t.last_correction_lag_ms},
          {"max_correction_lag_ms", t.max_correction_lag_ms},
          {"imu_accepted", i.accepted},
          {"imu_non_finite", i.non_finite},
          {"imu_out_of_range", i.out_of_range},
          {"imu_out_of_order", i.out_of_order},
          {"imu_duplicate", i.duplicate}};
}

hsslam::odometry_t pose_msg(const FrameResult& r) {
  if (!r.accepted || r.state == TrackState::kInitialising)
    throw std::invalid_argument("pose_msg: frame has no state");
  hsslam::odometry_t msg =
      odometry_to_msg(r.nav, r.seq, r.map_id, static_cast<int8_t>(r.state), r.quality);
  msg.t_ns = r.t_ns;
  for (int row = 0; row < 6; ++row)
    for (int col = 0; col < 6; ++col) msg.covariance[row * 6 + col] = r.pose_covariance(row, col);
  return msg;
}

hsslam::tracker_status_t status_msg(const FrameResult& r, const std::vector<NamedCounter>& counters,
                                    const std::string& message) {
  hsslam::tracker_status_t msg;
  msg.t_ns = r.t_ns;
  msg.seq = r.seq;
  msg.state = static_cast<int8_t>(r.state);
  msg.method = static_cast<int8_t>(r.method);
  msg.is_keyframe = r.is_keyframe;
  msg.tracked_points = r.tracked_points;
  for (const auto& [name, ms] : r.stage_ms) {
    msg.stage_names.push_back(name);
    msg.stage_ms.push_back(ms);
  }
  msg.num_stages = static_cast<int32_t>(msg.stage_names.size());
  msg.total_ms = r.total_ms;
  for (const auto& [name, value] : counters) {
    msg.counter_names.push_back(name);
    msg.counter_values.push_back(value);
  }
  msg.num_counters = static_cast<int32_t>(msg.counter_names.size());
  msg.message = message;
  for (const FrameFeature& f : r.features) {
    msg.feature_u.push_back(f.uv.x());
    msg.feature_v.push_back(f.uv.y());
    msg.feature_source.push_back(static_cast<int8_t>(f.source));
  }
  msg.num_features = static_cast<int32_t>(r.features.size());
  return msg;
}

hsslam::keyframe_t keyframe_msg(const Keyframe& kf, const LocalMap& map, int32_t map_id) {
  hsslam::keyframe_t msg;
  msg.t_ns = kf.state.t_ns;
  msg.map_id = map_id;
  msg.pose = keyframe_pose_to_msg(kf.id, kf.state);
  msg.prev_keyframe_id = kf.prev_keyframe_id;
  const auto positions = map.point_positions(kf);
  const OrbFeatures& f = kf.features;
  std::unordered_set<int64_t> sent;
  for (size_t i = 0; i < f.size(); ++i) {
    const cv::KeyPoint& k = f.keypoints[i];
    hsslam::keypoint_t kp;
    kp.u = k.pt.x;
    kp.v = k.pt.y;
    kp.u_right = kf.uv_right.at(i).x();
    kp.v_right = kf.uv_right.at(i).y();
    kp.depth = kf.depth.at(i);
    kp.octave = static_cast<int8_t>(k.octave);
    kp.angle = k.angle;
    kp.map_point_id = positions.at(i) ? kf.point_ids.at(i) : -1;
    msg.keypoints.push_back(kp);
    msg.descriptors.emplace_back(f.descriptors.ptr<uint8_t>(static_cast<int>(i)),
                                 f.descriptors.ptr<uint8_t>(static_cast<int>(i)) + 32);
    if (kp.map_point_id >= 0 && sent.insert(kp.map_point_id).second) {
      hsslam::map_point_t p;
      p.id = kp.map_point_id;
      copy3(*positions[i], p.p_w);
      msg.points.push_back(p);
    }
  }
  msg.num_keypoints = static_cast<int32_t>(msg.keypoints.size());
  msg.num_points = static_cast<int32_t>(msg.points.size());
  if (!kf.imu.empty()) msg.imu = imu_batch_to_msg(kf.imu, 0).samples;
  msg.num_imu = static_cast<int32_t>(msg.imu.size());
  return msg;
}

hsslam::reloc_request_t reloc_request_msg(const AtlasQuery& q, int32_t map_id) {
  hsslam::reloc_request_t msg{};
  msg.seq = q.seq;
  msg.next_map_id = q.next_map_id;
  msg.frame = keyframe_msg(*q.frame, *q.points, map_id);
  return msg;
}

}  // namespace hs
