#include "mapper/loop_closing.h"

#include <algorithm>

namespace hs {

LoopClosureStats close_loop(KeyframeGraph& graph, const std::vector<LoopFound>& loops,
                            const LoopClosingOptions& options) {
  LoopClosureStats stats;
  const int32_t world = graph.world(loops.back().query);
  std::map<int64_t, Eigen::Isometry3d> before;
  for (int64_t id : graph.keyframe_ids())
    if (graph.world(id) == world) before[id] = graph.keyframe(id)->state.T_w_b();
  const auto relative = [&](int64_t a, int64_t b) { return before.at(a).inverse() * before.at(b); };

  std::vector<PoseGraphEdge> edges;
  std::optional<int64_t> previous;
  for (const auto& [id, T] : before) {
    if (previous) edges.push_back({*previous, id, relative(*previous, id), 1.0});
    previous = id;
    for (int64_t other : graph.most_covisible(id, 10))
      if (other < id && before.count(other) &&
          graph.shared_points(id, other) >= options.strong_covisibility)
        edges.push_back({other, id, relative(other, id), 1.0});
  }
  for (const LoopFound& l : loops)
    if (before.count(l.query) && before.count(l.candidate))
      edges.push_back({l.candidate, l.query, l.T_c_q, options.loop_weight});

  PoseGraphResult result =
      optimise_pose_graph(before, edges, before.begin()->first, options.pose_graph);
  std::map<int64_t, Eigen::Isometry3d> delta;
  for (const auto& [id, T] : result.T_w_b) {
    delta[id] = T * before.at(id).inverse();
    NavState s = graph.keyframe(id)->state;
    s.set_T_w_b(T);
    s.v_w = delta[id].linear() * s.v_w;
    graph.set_state(id, s);
    stats.max_shift_m = std::max(stats.max_shift_m, delta[id].translation().norm());
  }
  for (int64_t id : graph.point_ids()) {
    const MapperPoint& p = *graph.point(id);
    for (const Observation& o : p.observations) {
      if (!delta.count(o.keyframe_id)) continue;
      graph.set_position(id, delta.at(o.keyframe_id) * p.p_w);
      ++stats.points_moved;
      break;
    }
  }
  stats.keyframes = static_cast<int>(before.size());
  stats.edges = static_cast<int>(edges.size());
  result.T_w_b.clear();
  stats.graph = std::move(result);
  return stats;
}

}  // namespace hs
