#include "mapper/window_input.h"

#include <algorithm>
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
                         const WindowInputOptions& options) {
  WindowInput out;
  LocalBaInput& in = out.input;
  const std::set<int64_t> free(window.keyframes.begin(), window.keyframes.end());
  std::set<int64_t> fixed(window.fixed_keyframes.begin(), window.fixed_keyframes.end());
  const auto near = [&](int64_t keyframe, const Eigen::Vector3d& p_w) {
    return (graph.keyframe(keyframe)->state.p_w_b - p_w).norm() < options.fixed_point_distance_m;
  };
  const auto far = [&](const MapperPoint& p) {
    if (options.fixed_point_distance_m <= 0) return false;
    if (options.far_from_observers)
      return std::none_of(p.observations.begin(), p.observations.end(),
                          [&](const Observation& o) { return near(o.keyframe_id, p.p_w); });
    return std::none_of(free.begin(), free.end(), [&](int64_t k) { return near(k, p.p_w); });
  };
  // The IMU factor into the oldest optimised keyframes needs their predecessor, held fixed.
  for (int64_t id : free)
    if (const auto prev = graph.imu_predecessor(id); prev && !free.count(*prev))
      fixed.insert(*prev);

  for (int64_t id : free) in.keyframes.push_back({id, graph.keyframe(id)->state, false});
  for (int64_t id : fixed) in.keyframes.push_back({id, graph.keyframe(id)->state, true});
  // A point only one keyframe sees constrains no pose: it would only cost time (on
  // vehicle_loop a third of the window's points are the new keyframe's own).
  std::unordered_set<int64_t> points;
  for (int64_t id : window.points) {
    const MapperPoint& p = *graph.point(id);
    if (p.observations.size() < 2) continue;
    points.insert(id);
    in.points.push_back({id, p.p_w, far(p)});
  }

  for (const BaKeyframe& k : in.keyframes) {
    const MapperKeyframe& kf = *graph.keyframe(k.id);
    for (const MapperKeypoint& kp : kf.keypoints) {
      if (kp.point_id < 0 || !points.count(kp.point_id)) continue;
      const double sigma = (kp.detected ? options.detected_pixel_sigma : options.pixel_sigma) *
                           std::pow(options.octave_scale, kp.octave);
      const Eigen::Vector2d uv(kp.u, kp.v);
      in.observations.push_back({k.id, kp.point_id, 0, uv, sigma});
      if (kp.u_right < 0.f) continue;
      in.observations.push_back(
          {k.id, kp.point_id, 1, Eigen::Vector2d(kp.u_right, kp.v_right), sigma});
    }
  }

  std::set<int64_t> all = free;
  all.insert(fixed.begin(), fixed.end());
  in.imu_factors = chain_imu_factors(graph, all, fixed, options, &out.imu_factors_skipped);
  return out;
}

std::vector<BaImuFactor> chain_imu_factors(const KeyframeGraph& graph, const std::set<int64_t>& all,
                                           const std::set<int64_t>& fixed,
                                           const WindowInputOptions& options, int* skipped) {
  std::vector<BaImuFactor> factors;
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
      ++*skipped;
      continue;
    }
    factors.push_back({*i, j, std::move(pim)});
  }
  return factors;
}

}  // namespace hs
