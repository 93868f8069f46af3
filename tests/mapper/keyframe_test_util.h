#pragma once
// Hand-built KEYFRAME messages for the mapper tests, shaped like the tracker's (see
// tracker/node/node_messages.cpp keyframe_msg): one keypoint per observed point plus one without,
// IMU every 10 ms bracketing the interval since the previous keyframe.
#include <cstdint>
#include <vector>

#include "hsslam/keyframe_t.hpp"
#include "mapper/keyframe_from_msg.h"

namespace hs::test {

constexpr int64_t kImuStepNs = 10'000'000;

// Keyframes are 100 ms apart, moving 0.1 m along x per id.
inline int64_t keyframe_time(int64_t id) {
  return 1'000'000'000 + id * 100'000'000;
}

// Every point's descriptor, the same from every keyframe.
inline std::vector<uint8_t> point_descriptor(int64_t point_id) {
  std::vector<uint8_t> d(32);
  for (size_t b = 0; b < d.size(); ++b) d[b] = static_cast<uint8_t>(point_id * 37 + b * 11);
  return d;
}

// Ids first..last inclusive.
inline std::vector<int64_t> ids(int64_t first, int64_t last) {
  std::vector<int64_t> out;
  for (int64_t i = first; i <= last; ++i) out.push_back(i);
  return out;
}

inline hsslam::keyframe_t keyframe_msg(int64_t id, int64_t prev_id,
                                       const std::vector<int64_t>& point_ids, int32_t map_id = 0,
                                       int8_t octave = 0) {
  hsslam::keyframe_t m{};
  m.t_ns = keyframe_time(id);
  m.map_id = map_id;
  m.pose.id = id;
  m.pose.t_ns = m.t_ns;
  m.pose.p_w_b[0] = 0.1 * static_cast<double>(id);
  m.pose.q_w_b[0] = 1.0;
  m.pose.v_w[0] = 1.0;
  m.prev_keyframe_id = prev_id;
  for (size_t i = 0; i <= point_ids.size(); ++i) {
    const bool observes = i < point_ids.size();
    hsslam::keypoint_t k{};
    k.u = 20.f + 10.f * static_cast<float>(i);
    k.v = 100.f;
    k.u_right = k.u - 8.f;
    k.v_right = k.v + 0.5f;
    k.depth = 5.f;
    k.octave = octave;
    k.angle = 45.f;
    k.map_point_id = observes ? point_ids[i] : -1;
    m.keypoints.push_back(k);
    m.descriptors.push_back(point_descriptor(observes ? point_ids[i] : -1000 - id));
    if (!observes) continue;
    hsslam::map_point_t p{};
    p.id = point_ids[i];
    p.p_w[0] = 0.1 * static_cast<double>(p.id);
    p.p_w[2] = 5.0;
    m.points.push_back(p);
  }
  if (prev_id >= 0)
    for (int64_t t = keyframe_time(prev_id) - kImuStepNs / 2; t < m.t_ns + kImuStepNs;
         t += kImuStepNs) {
      hsslam::imu_sample_t s{};
      s.t_ns = t;
      s.gyro[2] = 0.01;
      s.accel[2] = 9.81;
      m.imu.push_back(s);
    }
  m.num_keypoints = static_cast<int32_t>(m.keypoints.size());
  m.num_points = static_cast<int32_t>(m.points.size());
  m.num_imu = static_cast<int32_t>(m.imu.size());
  return m;
}

inline MapperKeyframe keyframe(int64_t id, int64_t prev_id, const std::vector<int64_t>& point_ids,
                               int32_t map_id = 0, int8_t octave = 0) {
  return keyframe_from_msg(keyframe_msg(id, prev_id, point_ids, map_id, octave), "KEYFRAME");
}

}  // namespace hs::test
