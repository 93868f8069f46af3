// Mapper::map_file and Mapper::load: the mapper's state to and from a MapFile.
#include <stdexcept>

#include "mapper/mapper.h"

namespace hs {

MapFile Mapper::map_file() const {
  MapFile map;
  map.g_w = options_.localisation_only ? loaded_g_w_ : g_w_;
  for (int64_t id : graph_.keyframe_ids()) {
    if (options_.localisation_only && !loaded_keyframe(id)) continue;  // the map as loaded
    MapperKeyframe kf = *graph_.keyframe(id);
    for (const MapperKeypoint& kp : kf.keypoints)
      if (kp.point_id >= 0) kf.point_positions[kp.point_id] = graph_.point(kp.point_id)->p_w;
    map.keyframes.push_back(std::move(kf));
  }
  const auto saved = [&](int64_t id) {
    return graph_.keyframe(id) && (!options_.localisation_only || loaded_keyframe(id));
  };
  for (const LoopFound& l : closed_loops_)
    if (saved(l.query) && saved(l.candidate)) map.loops.push_back(l);
  return map;
}

namespace {
int64_t shift_point(int64_t id) {
  return id < 0 || id >= kLoadedPointIdBase ? id : id + kLoadedPointIdBase;
}
int64_t shift_keyframe(int64_t id) {
  return id < 0 || loaded_keyframe(id) ? id : id + kLoadedKeyframeIdBase;
}
}  // namespace

void Mapper::load(const MapFile& map) {
  if (graph_.num_keyframes() > 0)
    throw std::logic_error("Mapper::load: the mapper already has keyframes");
  for (MapperKeyframe kf : map.keyframes) {
    kf.id = shift_keyframe(kf.id);
    kf.prev_id = shift_keyframe(kf.prev_id);
    if (kf.map_id < kLoadedMapIdBase) kf.map_id += kLoadedMapIdBase;
    for (MapperKeypoint& kp : kf.keypoints) kp.point_id = shift_point(kp.point_id);
    std::unordered_map<int64_t, Eigen::Vector3d> positions;
    for (const auto& [id, p_w] : kf.point_positions) positions[shift_point(id)] = p_w;
    kf.point_positions = positions;
    graph_.insert(kf);
    for (const auto& [id, p_w] : positions) {
      graph_.set_position(id, p_w);
      loaded_points_.insert(id);
    }
    if (options_.loop.enabled) loops_.add(graph_, kf.id);
  }
  for (LoopFound l : map.loops) {
    l.query = shift_keyframe(l.query);
    l.candidate = shift_keyframe(l.candidate);
    closed_loops_.push_back(l);
  }
  g_w_ = loaded_g_w_ = map.g_w.isZero() ? default_gravity_w() : map.g_w;
}

}  // namespace hs
