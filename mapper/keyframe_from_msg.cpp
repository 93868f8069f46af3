#include "mapper/keyframe_from_msg.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "common/core/error.h"
#include "common/lcm/convert.h"
#include "hsslam/imu_batch_t.hpp"

namespace hs {
namespace {

bool finite3(const double* v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

MapperKeypoint keypoint_from_msg(const hsslam::keypoint_t& k, const std::string& where) {
  const auto fail = [&](const std::string& what) { throw InputError(where, what); };
  if (!std::isfinite(k.u) || !std::isfinite(k.v) || !std::isfinite(k.angle))
    fail("non-finite u, v or angle");
  const bool no_right = k.u_right == -1.f && k.v_right == -1.f;
  if (!no_right && !(std::isfinite(k.u_right) && k.u_right >= 0.f && std::isfinite(k.v_right) &&
                     k.v_right >= 0.f))
    fail("right pixel (" + std::to_string(k.u_right) + ", " + std::to_string(k.v_right) +
         ") (expected -1 -1 or both >= 0)");
  if (k.depth != -1.f && !(std::isfinite(k.depth) && k.depth > 0.f))
    fail("depth " + std::to_string(k.depth) + " (expected -1 or > 0)");
  if (k.octave < 0) fail("negative octave " + std::to_string(k.octave));
  if (k.map_point_id < -1) fail("map_point_id " + std::to_string(k.map_point_id));
  return {k.u,      k.v,     k.u_right,      k.v_right,         k.depth,
          k.octave, k.angle, k.map_point_id, k.map_point_id < 0};
}

std::vector<ImuSample> imu_from_msg(const hsslam::keyframe_t& msg, const std::string& where) {
  if (msg.num_imu < 0 || static_cast<size_t>(msg.num_imu) != msg.imu.size())
    throw InputError(where, "num_imu " + std::to_string(msg.num_imu) + " but " +
                                std::to_string(msg.imu.size()) + " samples");
  if (msg.imu.empty()) return {};
  hsslam::imu_batch_t batch;  // imu_batch_from_msg checks finiteness and time order
  batch.t_ns = msg.imu.back().t_ns;
  batch.seq = 0;
  batch.num_samples = msg.num_imu;
  batch.samples = msg.imu;
  std::vector<ImuSample> samples = imu_batch_from_msg(batch, where + ": imu");
  if (samples.size() >= 2 && samples[samples.size() - 2].t_ns >= msg.t_ns)
    throw InputError(where, "IMU samples extend past the keyframe time " +
                                std::to_string(msg.t_ns) + " (only the last may)");
  return samples;
}

}  // namespace

MapperKeyframe keyframe_from_msg(const hsslam::keyframe_t& msg, const std::string& source) {
  const std::string where = source + ": keyframe " + std::to_string(msg.pose.id);
  const auto fail = [&](const std::string& what) { throw InputError(where, what); };
  MapperKeyframe kf;
  kf.id = msg.pose.id;
  kf.map_id = msg.map_id;
  kf.prev_id = msg.prev_keyframe_id;
  if (kf.id < 0) fail("negative id");
  if (msg.t_ns != msg.pose.t_ns)
    fail("t_ns " + std::to_string(msg.t_ns) + " differs from pose.t_ns " +
         std::to_string(msg.pose.t_ns));
  if (kf.prev_id < -1 || kf.prev_id >= kf.id)
    fail("prev_keyframe_id " + std::to_string(kf.prev_id) + " (expected -1 or in [0, id))");
  kf.state = keyframe_pose_from_msg(msg.pose, where + ": pose");

  const size_t n = msg.keypoints.size();
  if (msg.num_keypoints < 0 || static_cast<size_t>(msg.num_keypoints) != n ||
      msg.descriptors.size() != n)
    fail("num_keypoints " + std::to_string(msg.num_keypoints) + " but " + std::to_string(n) +
         " keypoints and " + std::to_string(msg.descriptors.size()) + " descriptors");
  if (msg.num_points < 0 || static_cast<size_t>(msg.num_points) != msg.points.size())
    fail("num_points " + std::to_string(msg.num_points) + " but " +
         std::to_string(msg.points.size()) + " points");

  for (const hsslam::map_point_t& p : msg.points) {
    const std::string point = "point " + std::to_string(p.id);
    if (p.id < 0) fail(point + ": negative id");
    if (!finite3(p.p_w)) fail(point + ": non-finite p_w");
    if (!kf.point_positions.emplace(p.id, Eigen::Vector3d(p.p_w[0], p.p_w[1], p.p_w[2])).second)
      fail(point + " listed twice");
  }

  std::unordered_map<int64_t, size_t> observer;  // point id -> keypoint index
  kf.keypoints.reserve(n);
  kf.descriptors.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const std::string keypoint = "keypoint " + std::to_string(i);
    kf.keypoints.push_back(keypoint_from_msg(msg.keypoints[i], where + ": " + keypoint));
    if (msg.descriptors[i].size() != kf.descriptors[i].size())
      fail(keypoint + ": descriptor of " + std::to_string(msg.descriptors[i].size()) +
           " bytes (expected 32)");
    std::copy(msg.descriptors[i].begin(), msg.descriptors[i].end(), kf.descriptors[i].begin());
    const int64_t id = kf.keypoints.back().point_id;
    if (id < 0) continue;
    if (!kf.point_positions.count(id))
      fail(keypoint + " observes point " + std::to_string(id) + ", which is not in the message");
    if (const auto [it, fresh] = observer.emplace(id, i); !fresh)
      fail("keypoints " + std::to_string(it->second) + " and " + std::to_string(i) +
           " both observe point " + std::to_string(id));
  }
  if (observer.size() != kf.point_positions.size())
    fail(std::to_string(kf.point_positions.size() - observer.size()) +
         " points are observed by no keypoint");
  kf.imu = imu_from_msg(msg, where);
  return kf;
}

RelocRequest reloc_request_from_msg(const hsslam::reloc_request_t& msg, const std::string& source) {
  const std::string where = source + ": reloc_request_t seq " + std::to_string(msg.seq);
  if (msg.next_map_id < 0 || msg.next_map_id == msg.frame.map_id)
    throw InputError(where, "next_map_id " + std::to_string(msg.next_map_id) + " (map id " +
                                std::to_string(msg.frame.map_id) + ")");
  return {msg.seq, msg.next_map_id, keyframe_from_msg(msg.frame, where)};
}

}  // namespace hs
