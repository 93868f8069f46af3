#include "mapper/window_input.h"

#include <cmath>
#include <set>
#include <unordered_set>

#include "common/imu/preintegration.h"

namespace hs {
namespace {

ImuBias bias_of(const NavState& x) {
  ImuBias b;
  b.gyro = x.gyro_bias;
  b.accel = x.accel_bias;
  return b;
}

}  // namespace

WindowInput window_input(const KeyframeGraph& graph, const LocalWindow& window,
                         const StereoCalib& calib, const WindowInputOptions& options) {
  WindowInput out;
  LocalBaInput& in = out.input;
  const std::set<int64_t> free(window.keyframes.begin(), window.keyframes.end());
  std::set<int64_t> fixed(window.fixed_keyframes.begin(), window.fixed_keyframes.end());
  // The IMU factor into the oldest optimised keyframes needs their predecessor, held fixed.
  for (int64_t id : free)
    if (const auto prev = graph.imu_predecessor(id); prev && !free.count(*prev))
      fixed.insert(*prev);

  for (int64_t id : free) in.keyframes.push_back({id, graph.keyframe(id)->state, false});
  for (int64_t id : fixed) in.keyframes.push_back({id, graph.keyframe(id)->state, true});
  const std::unordered_set<int64_t> points(window.points.begin(), window.points.end());
  for (int64_t id : window.points) in.points.push_back({id, graph.point(id)->p_w, false});

  const Eigen::Isometry3d T_c1_c0 = calib.T_c0_c1().inverse();
  for (const BaKeyframe& k : in.keyframes) {
    const MapperKeyframe& kf = *graph.keyframe(k.id);
    for (const MapperKeypoint& kp : kf.keypoints) {
      if (kp.point_id < 0 || !points.count(kp.point_id)) continue;
      const double sigma = options.pixel_sigma * std::pow(options.octave_scale, kp.octave);
      const Eigen::Vector2d uv(kp.u, kp.v);
      in.observations.push_back({k.id, kp.point_id, 0, uv, sigma});
      if (kp.u_right < 0.f || kp.depth <= 0.f) continue;
      const Eigen::Vector2d xy = calib.cam0.intrinsics.unproject_normalised(uv);
      const Eigen::Vector3d p_c1 = T_c1_c0 * (Eigen::Vector3d(xy.x(), xy.y(), 1.0) * kp.depth);
      Eigen::Vector2d uv_right;
      if (!calib.cam1.intrinsics.project(p_c1, &uv_right)) continue;
      uv_right.x() = kp.u_right;
      in.observations.push_back({k.id, kp.point_id, 1, uv_right, sigma});
    }
  }

  const std::set<int64_t> all = [&] {
    std::set<int64_t> s = free;
    s.insert(fixed.begin(), fixed.end());
    return s;
  }();
  for (int64_t j : all) {
    const auto i = graph.imu_predecessor(j);
    if (!i || !all.count(*i) || (fixed.count(*i) && fixed.count(j))) continue;
    const MapperKeyframe& kf_i = *graph.keyframe(*i);
    const MapperKeyframe& kf_j = *graph.keyframe(j);
    ImuPreintegration pim =
        preintegrate(kf_j.imu, kf_i.state.t_ns, kf_j.state.t_ns, bias_of(kf_i.state), options.imu);
    const ImuIntegrationStatus& s = pim.status();
    if (pim.t1_ns() != kf_j.state.t_ns || s.nonfinite_rejected > 0 ||
        s.largest_gap_ns > options.max_imu_gap_ns || s.extrapolated_ns > options.max_imu_gap_ns) {
      ++out.imu_factors_skipped;
      continue;
    }
    in.imu_factors.push_back({*i, j, std::move(pim)});
  }
  return out;
}

}  // namespace hs
