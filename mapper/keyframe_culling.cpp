#include "mapper/keyframe_culling.h"

#include <algorithm>
#include <unordered_set>

namespace hs {
namespace {

bool points_seen_elsewhere(const KeyframeGraph& graph, const MapperKeyframe& kf,
                           const std::unordered_set<int64_t>& culled,
                           const CullingOptions& options) {
  int points = 0, covered = 0;
  for (const MapperKeypoint& kp : kf.keypoints) {
    if (kp.point_id < 0) continue;
    ++points;
    int observers = 0;
    for (const Observation& o : graph.point(kp.point_id)->observations) {
      if (o.keyframe_id == kf.id || culled.count(o.keyframe_id)) continue;
      const MapperKeyframe& other = *graph.keyframe(o.keyframe_id);
      if (graph.world(other.id) == graph.world(kf.id) &&
          other.keypoints[static_cast<size_t>(o.keypoint)].octave <=
              kp.octave + options.octave_slack)
        ++observers;
    }
    if (observers >= options.min_observers) ++covered;
  }
  return points > 0 && covered >= options.redundant_ratio * points;
}

// Whether the IMU interval that replaces `id`'s two (and those of culled neighbours) stays short.
bool merged_imu_span_ok(const KeyframeGraph& graph, int64_t id,
                        const std::unordered_set<int64_t>& culled, const CullingOptions& options) {
  std::optional<int64_t> prev = graph.imu_predecessor(id), next = graph.imu_successor(id);
  while (prev && culled.count(*prev)) prev = graph.imu_predecessor(*prev);
  while (next && culled.count(*next)) next = graph.imu_successor(*next);
  return !prev || !next ||
         graph.keyframe(*next)->state.t_ns - graph.keyframe(*prev)->state.t_ns <=
             options.max_imu_span_ns;
}

}  // namespace

std::vector<int64_t> redundant_keyframes(const KeyframeGraph& graph,
                                         std::vector<int64_t> candidates,
                                         const CullingOptions& options) {
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  const std::vector<int64_t> all = graph.keyframe_ids();
  const std::unordered_set<int64_t> recent(
      all.end() - static_cast<ptrdiff_t>(std::min(options.keep_recent, all.size())), all.end());
  std::unordered_set<int64_t> culled;
  std::vector<int64_t> redundant;
  for (int64_t id : candidates) {
    const MapperKeyframe* kf = graph.keyframe(id);
    if (!kf || recent.count(id)) continue;
    if (points_seen_elsewhere(graph, *kf, culled, options) &&
        merged_imu_span_ok(graph, id, culled, options)) {
      culled.insert(id);
      redundant.push_back(id);
    }
  }
  return redundant;
}

}  // namespace hs
