// Mapper::map_file and Mapper::load: the mapper's state to and from a MapFile.
#include <stdexcept>

#include "mapper/mapper.h"

namespace hs {

MapFile Mapper::map_file() const {
  MapFile map;
  map.g_w = g_w_;
  map.loops = closed_loops_;
  for (int64_t id : graph_.keyframe_ids()) {
    MapperKeyframe kf = *graph_.keyframe(id);
    for (const MapperKeypoint& kp : kf.keypoints)
      if (kp.point_id >= 0) kf.point_positions[kp.point_id] = graph_.point(kp.point_id)->p_w;
    map.keyframes.push_back(std::move(kf));
  }
  return map;
}

namespace {
// A loaded map's ids move out of the way of the tracker that runs now, whose keyframe, point
// and map ids start again from 0: the loaded map is a world of its own.
constexpr int64_t kLoadedKeyframeShift = int64_t{1} << 48;
constexpr int64_t kLoadedPointShift = int64_t{1} << 56;  // tracker points only (< 2^60)
constexpr int32_t kLoadedMapShift = int32_t{1} << 24;

int64_t shift_point(int64_t id) {
  return id < 0 || mapper_made_point(id) ? id : id + kLoadedPointShift;
}
int64_t shift_keyframe(int64_t id) {
  return id < 0 ? id : id + kLoadedKeyframeShift;
}
}  // namespace

void Mapper::load(const MapFile& map) {
  if (graph_.num_keyframes() > 0)
    throw std::logic_error("Mapper::load: the mapper already has keyframes");
  for (MapperKeyframe kf : map.keyframes) {
    kf.id = shift_keyframe(kf.id);
    kf.prev_id = shift_keyframe(kf.prev_id);
    kf.map_id += kLoadedMapShift;
    for (MapperKeypoint& kp : kf.keypoints) kp.point_id = shift_point(kp.point_id);
    std::unordered_map<int64_t, Eigen::Vector3d> positions;
    for (const auto& [id, p_w] : kf.point_positions) positions[shift_point(id)] = p_w;
    kf.point_positions = positions;
    graph_.insert(kf);
    for (const auto& [id, p_w] : positions) graph_.set_position(id, p_w);
    if (options_.loop.enabled) loops_.add(graph_, kf.id);
  }
  for (LoopFound l : map.loops) {
    l.query = shift_keyframe(l.query);
    l.candidate = shift_keyframe(l.candidate);
    closed_loops_.push_back(l);
  }
  g_w_ = map.g_w.isZero() ? default_gravity_w() : map.g_w;
}

}  // namespace hs
