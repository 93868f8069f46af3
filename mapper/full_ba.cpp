#include "mapper/full_ba.h"

#include <set>
#include <unordered_map>

namespace hs {

LocalBaInput full_ba_input(const KeyframeGraph& graph, int32_t world, const Eigen::Vector3d& g_w,
                           WindowInputOptions options, const std::function<bool(int64_t)>& frozen) {
  LocalWindow window;
  std::set<int64_t> points;
  for (int64_t k : graph.keyframe_ids()) {
    if (graph.world(k) != world) continue;
    (frozen && frozen(k) ? window.fixed_keyframes : window.keyframes).push_back(k);
    for (const MapperKeypoint& kp : graph.keyframe(k)->keypoints)
      if (kp.point_id >= 0) points.insert(kp.point_id);
  }
  window.points.assign(points.begin(), points.end());
  // A point far from every keyframe seeing it: its stereo depth is all that fixes it.
  options.far_from_observers = true;
  LocalBaInput input = window_input(graph, window, options).input;
  input.gravity = {g_w, 0.0};
  return input;
}

namespace {

bool same_pose(const NavState& a, const NavState& b) {
  return a.p_w_b == b.p_w_b && a.q_w_b.coeffs() == b.q_w_b.coeffs();
}

}  // namespace

FullBaApplied apply_full_ba(KeyframeGraph& graph, const LocalBaInput& input,
                            const LocalBaResult& result) {
  FullBaApplied applied;
  std::unordered_map<int64_t, Eigen::Isometry3d> correction;  // keyframe -> result * snapshot^-1
  struct Newest {
    int64_t t_ns = -1;
    Eigen::Isometry3d C = Eigen::Isometry3d::Identity();
  };
  std::unordered_map<int32_t, Newest> newest;  // per world, its newest optimised keyframe's
  for (size_t n = 0; n < input.keyframes.size(); ++n) {
    const NavState& before = input.keyframes[n].state;
    const NavState& after = result.keyframes[n].state;
    const int64_t id = input.keyframes[n].id;
    const MapperKeyframe* kf = graph.keyframe(id);
    if (!kf) continue;  // culled since
    const Eigen::Isometry3d C = after.T_w_b() * before.T_w_b().inverse();
    correction[id] = C;
    Newest& w = newest[graph.world(id)];
    if (before.t_ns > w.t_ns) w = {before.t_ns, C};
    graph.set_state(id, same_pose(kf->state, before) ? after : transformed(kf->state, C));
    ++applied.keyframes;
  }
  for (int64_t id : graph.keyframe_ids()) {
    const MapperKeyframe& kf = *graph.keyframe(id);
    const auto w = newest.find(graph.world(id));
    if (correction.count(id) || w == newest.end() || kf.state.t_ns <= w->second.t_ns) continue;
    correction[id] = w->second.C;
    graph.set_state(id, transformed(kf.state, w->second.C));
    ++applied.keyframes_moved;
  }

  std::unordered_map<int64_t, size_t> optimised;
  for (size_t n = 0; n < input.points.size(); ++n) optimised[input.points[n].id] = n;
  for (int64_t id : graph.point_ids()) {
    const MapperPoint& p = *graph.point(id);
    const auto o = optimised.find(id);
    if (o != optimised.end() && p.p_w == input.points[o->second].p_w) {
      graph.set_position(id, result.points[o->second].p_w);
      ++applied.points;
      continue;
    }
    for (const Observation& ob : p.observations) {
      const auto c = correction.find(ob.keyframe_id);
      if (c == correction.end()) continue;
      graph.set_position(id, c->second * p.p_w);
      ++(o != optimised.end() ? applied.points : applied.points_moved);
      break;
    }
  }
  return applied;
}

}  // namespace hs
