#include "mapper/keyframe_graph.h"

#include <algorithm>
#include <climits>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

namespace hs {

KeyframeGraph::InsertResult KeyframeGraph::insert(MapperKeyframe kf) {
  if (kf.descriptors.size() != kf.keypoints.size())
    throw std::invalid_argument("KeyframeGraph::insert: keyframe " + std::to_string(kf.id) +
                                " has a descriptor count unlike its keypoint count");
  for (const MapperKeypoint& k : kf.keypoints)
    if (k.point_id >= 0 && !points_.count(k.point_id) && !kf.point_positions.count(k.point_id))
      throw std::invalid_argument("KeyframeGraph::insert: keyframe " + std::to_string(kf.id) +
                                  " observes point " + std::to_string(k.point_id) +
                                  " without a position");
  if (!seen_ids_.insert(kf.id).second) {
    ++counters_.duplicates;
    return InsertResult::kDuplicate;
  }
  ++counters_.inserted;
  if (kf.id < max_id_) ++counters_.out_of_order;
  max_id_ = std::max(max_id_, kf.id);
  if (last_map_id_ && *last_map_id_ != kf.map_id) ++counters_.map_changes;
  last_map_id_ = kf.map_id;
  const auto [world_it, fresh] = world_of_map_.try_emplace(kf.map_id, kf.map_id);
  if (fresh) {
    const auto prev = keyframes_.find(kf.prev_id);
    if (kf.prev_id >= 0 && prev != keyframes_.end())
      world_it->second = world_of_map_.at(prev->second.kf.map_id);
    else
      ++counters_.new_worlds;
  }
  const int32_t w = world_it->second;
  if (kf.prev_id >= 0) {
    if (!successor_.emplace(kf.prev_id, kf.id).second) {
      ++counters_.forks;
      kf.prev_id = -1;
    } else if (!keyframes_.count(kf.prev_id)) {
      ++counters_.missing_prev;
    }
  }

  const int64_t id = kf.id;
  Node& n = keyframes_[id];
  n.kf = std::move(kf);
  for (size_t i = 0; i < n.kf.keypoints.size(); ++i) {
    const int64_t point_id = n.kf.keypoints[i].point_id;
    if (point_id < 0) continue;
    auto [it, fresh] = points_.try_emplace(point_id);
    MapperPoint& p = it->second;
    if (fresh) {
      p.id = point_id;
      p.p_w = n.kf.point_positions.at(point_id);
      p.first_keyframe_id = id;
      if (mapper_made_point(point_id)) next_point_id_ = std::max(next_point_id_, point_id + 1);
    }
    for (const Observation& o : p.observations)
      if (world(o.keyframe_id) == w) add_weight(id, o.keyframe_id, 1);
    p.observations.push_back({id, static_cast<int>(i)});
    update_descriptor(p);
  }
  n.kf.point_positions.clear();  // the store's positions are the only truth from here on
  return InsertResult::kInserted;
}

bool KeyframeGraph::remove_keyframe(int64_t id) {
  const auto it = keyframes_.find(id);
  if (it == keyframes_.end()) return false;
  Node& n = it->second;
  for (const auto& edge : n.covisibility) keyframes_.at(edge.first).covisibility.erase(id);
  for (const MapperKeypoint& k : n.kf.keypoints) {
    if (k.point_id < 0) continue;
    MapperPoint& p = points_.at(k.point_id);
    p.observations.erase(std::remove_if(p.observations.begin(), p.observations.end(),
                                        [id](const Observation& o) { return o.keyframe_id == id; }),
                         p.observations.end());
    if (p.observations.empty())
      points_.erase(k.point_id);
    else
      update_descriptor(p);
  }

  // Relink the chain around the removed keyframe: its successor's IMU interval now starts at
  // the removed keyframe's predecessor.
  const int64_t prev = n.kf.prev_id;
  if (const auto s = successor_.find(prev); prev >= 0 && s != successor_.end() && s->second == id)
    successor_.erase(s);
  if (const auto s = successor_.find(id); s != successor_.end()) {
    MapperKeyframe& next = keyframes_.at(s->second).kf;
    std::vector<ImuSample> merged = std::move(n.kf.imu);
    for (const ImuSample& sample : next.imu)
      if (merged.empty() || sample.t_ns > merged.back().t_ns) merged.push_back(sample);
    next.imu = std::move(merged);
    next.prev_id = prev;
    if (prev >= 0) successor_[prev] = s->second;
    successor_.erase(s);
  }
  keyframes_.erase(it);
  return true;
}

bool KeyframeGraph::remove_point(int64_t id) {
  const auto it = points_.find(id);
  if (it == points_.end()) return false;
  const std::vector<Observation>& obs = it->second.observations;
  for (size_t i = 0; i < obs.size(); ++i) {
    MapperKeyframe& a = keyframes_.at(obs[i].keyframe_id).kf;
    a.keypoints[static_cast<size_t>(obs[i].keypoint)].point_id = -1;
    for (size_t j = i + 1; j < obs.size(); ++j)
      if (world(obs[j].keyframe_id) == world(obs[i].keyframe_id))
        add_weight(obs[i].keyframe_id, obs[j].keyframe_id, -1);
  }
  points_.erase(it);
  return true;
}

int64_t KeyframeGraph::add_point(const Eigen::Vector3d& p_w,
                                 const std::vector<Observation>& observations) {
  const auto keypoint = [this](const Observation& o) -> MapperKeypoint& {
    return keyframes_.at(o.keyframe_id).kf.keypoints.at(static_cast<size_t>(o.keypoint));
  };
  for (const Observation& o : observations)
    if (keypoint(o).point_id >= 0)
      throw std::invalid_argument("KeyframeGraph::add_point: keypoint " +
                                  std::to_string(o.keypoint) + " of keyframe " +
                                  std::to_string(o.keyframe_id) + " already sees a point");
  const int64_t id = next_point_id_++;
  MapperPoint& p = points_[id];
  p.id = id;
  p.p_w = p_w;
  p.first_keyframe_id = observations.front().keyframe_id;
  for (const Observation& o : observations) {
    keypoint(o).point_id = id;
    for (const Observation& seen : p.observations) add_weight(o.keyframe_id, seen.keyframe_id, 1);
    p.observations.push_back(o);
  }
  update_descriptor(p);
  return id;
}

void KeyframeGraph::add_observation(int64_t id, const Observation& o) {
  MapperPoint& p = points_.at(id);
  MapperKeypoint& kp =
      keyframes_.at(o.keyframe_id).kf.keypoints.at(static_cast<size_t>(o.keypoint));
  const bool seen =
      std::any_of(p.observations.begin(), p.observations.end(),
                  [&](const Observation& s) { return s.keyframe_id == o.keyframe_id; });
  if (kp.point_id >= 0 || seen)
    throw std::invalid_argument("KeyframeGraph::add_observation: keyframe " +
                                std::to_string(o.keyframe_id) + " already sees point " +
                                std::to_string(seen ? id : kp.point_id));
  kp.point_id = id;
  for (const Observation& s : p.observations)
    if (world(s.keyframe_id) == world(o.keyframe_id)) add_weight(o.keyframe_id, s.keyframe_id, 1);
  p.observations.push_back(o);
  update_descriptor(p);
}

void KeyframeGraph::fuse_point(int64_t drop, int64_t keep, bool moved_as_detections) {
  if (drop == keep) return;
  const std::vector<Observation> moved = points_.at(drop).observations;
  const MapperPoint& kept = points_.at(keep);
  remove_point(drop);
  for (const Observation& o : moved) {
    const bool sees =
        std::any_of(kept.observations.begin(), kept.observations.end(),
                    [&](const Observation& s) { return s.keyframe_id == o.keyframe_id; });
    if (sees) continue;
    add_observation(keep, o);
    if (moved_as_detections)
      keyframes_.at(o.keyframe_id).kf.keypoints.at(static_cast<size_t>(o.keypoint)).detected = true;
  }
}

void KeyframeGraph::merge_world(int32_t from, int32_t into) {
  for (auto& entry : world_of_map_)
    if (entry.second == from) entry.second = into;
}

std::optional<int32_t> KeyframeGraph::world_of_map(int32_t map_id) const {
  const auto it = world_of_map_.find(map_id);
  return it == world_of_map_.end() ? std::nullopt : std::optional<int32_t>(it->second);
}

bool KeyframeGraph::join_map(int32_t map_id, int32_t world) {
  return world_of_map_.emplace(map_id, world).second;
}

const MapperKeyframe* KeyframeGraph::keyframe(int64_t id) const {
  const auto it = keyframes_.find(id);
  return it == keyframes_.end() ? nullptr : &it->second.kf;
}

const MapperPoint* KeyframeGraph::point(int64_t id) const {
  const auto it = points_.find(id);
  return it == points_.end() ? nullptr : &it->second;
}

namespace {
template <typename Map>
std::vector<int64_t> sorted_keys(const Map& map) {
  std::vector<int64_t> ids;
  ids.reserve(map.size());
  for (const auto& entry : map) ids.push_back(entry.first);
  std::sort(ids.begin(), ids.end());
  return ids;
}
}  // namespace

std::vector<int64_t> KeyframeGraph::point_ids() const {
  return sorted_keys(points_);
}

std::vector<int64_t> KeyframeGraph::keyframe_ids() const {
  return sorted_keys(keyframes_);
}

void KeyframeGraph::set_state(int64_t keyframe_id, const NavState& state) {
  const auto it = keyframes_.find(keyframe_id);
  if (it == keyframes_.end())
    throw std::out_of_range("KeyframeGraph: no keyframe " + std::to_string(keyframe_id));
  MapperKeyframe& kf = it->second.kf;
  if (state.t_ns != kf.state.t_ns)
    throw std::invalid_argument("KeyframeGraph::set_state: time differs from keyframe " +
                                std::to_string(keyframe_id) + "'s");
  kf.state = state;
}

void KeyframeGraph::set_position(int64_t point_id, const Eigen::Vector3d& p_w) {
  const auto it = points_.find(point_id);
  if (it == points_.end())
    throw std::out_of_range("KeyframeGraph: no point " + std::to_string(point_id));
  it->second.p_w = p_w;
}

int KeyframeGraph::shared_points(int64_t a, int64_t b) const {
  const auto& c = node(a).covisibility;
  const auto it = c.find(b);
  return it == c.end() ? 0 : it->second;
}

std::vector<int64_t> KeyframeGraph::most_covisible(int64_t id, size_t n) const {
  std::vector<std::pair<int, int64_t>> by_weight;  // (weight, id)
  for (const auto& [other, weight] : node(id).covisibility) by_weight.emplace_back(weight, other);
  std::sort(by_weight.rbegin(), by_weight.rend());
  std::vector<int64_t> ids;
  for (size_t i = 0; i < std::min(n, by_weight.size()); ++i) ids.push_back(by_weight[i].second);
  return ids;
}

LocalWindow KeyframeGraph::local_window(int64_t id) const {
  const int32_t w = world(id);
  std::set<int64_t> window{id};
  for (int64_t k : most_covisible(id, options_.window_covisible))
    if (shared_points(id, k) >= options_.window_min_shared) window.insert(k);
  std::set<int64_t> points;
  for (int64_t k : window)
    for (const MapperKeypoint& kp : node(k).kf.keypoints)
      if (kp.point_id >= 0) points.insert(kp.point_id);
  std::map<int64_t, int> seen;  // fixed candidate -> window points it sees
  for (int64_t p : points)
    for (const Observation& o : points_.at(p).observations)
      if (!window.count(o.keyframe_id) && world(o.keyframe_id) == w) ++seen[o.keyframe_id];
  std::vector<std::pair<int, int64_t>> ranked;  // most points first, then newest
  for (const auto& [k, n] : seen) ranked.emplace_back(n, k);
  std::sort(ranked.begin(), ranked.end(), std::greater<>());
  if (options_.max_fixed_keyframes > 0 && ranked.size() > options_.max_fixed_keyframes)
    ranked.resize(options_.max_fixed_keyframes);
  std::set<int64_t> fixed;
  for (const auto& [n, k] : ranked) fixed.insert(k);
  return {
      {window.begin(), window.end()}, {points.begin(), points.end()}, {fixed.begin(), fixed.end()}};
}

std::optional<int64_t> KeyframeGraph::imu_predecessor(int64_t id) const {
  const MapperKeyframe& kf = node(id).kf;
  if (kf.prev_id < 0 || kf.imu.empty()) return std::nullopt;
  const auto prev = keyframes_.find(kf.prev_id);
  if (prev == keyframes_.end() || world(kf.prev_id) != world(id)) return std::nullopt;
  const int64_t t_prev = prev->second.kf.state.t_ns;
  // Samples are in time order: only the first (the interpolation bracket) may precede t_prev.
  if (t_prev >= kf.state.t_ns || (kf.imu.size() > 1 && kf.imu[1].t_ns < t_prev))
    return std::nullopt;
  return kf.prev_id;
}

int32_t KeyframeGraph::world(int64_t keyframe_id) const {
  return world_of_map_.at(node(keyframe_id).kf.map_id);
}

std::optional<int64_t> KeyframeGraph::imu_successor(int64_t id) const {
  const auto s = successor_.find(id);
  if (s == successor_.end() || imu_predecessor(s->second) != id) return std::nullopt;
  return s->second;
}

const KeyframeGraph::Node& KeyframeGraph::node(int64_t id) const {
  const auto it = keyframes_.find(id);
  if (it == keyframes_.end())
    throw std::out_of_range("KeyframeGraph: no keyframe " + std::to_string(id));
  return it->second;
}

void KeyframeGraph::add_weight(int64_t a, int64_t b, int delta) {
  for (const auto& [from, to] : {std::pair(a, b), std::pair(b, a)}) {
    auto& c = keyframes_.at(from).covisibility;
    if ((c[to] += delta) <= 0) c.erase(to);
  }
}

void KeyframeGraph::update_descriptor(MapperPoint& p) const {
  std::vector<const Descriptor*> d;
  for (const Observation& o : p.observations)
    d.push_back(&node(o.keyframe_id).kf.descriptors.at(static_cast<size_t>(o.keypoint)));
  size_t best = 0;
  int best_median = INT_MAX;
  std::vector<int> dist;
  for (size_t i = 0; i < d.size() && d.size() > 1; ++i) {
    dist.clear();
    for (size_t j = 0; j < d.size(); ++j)
      if (j != i) dist.push_back(hamming_distance(*d[i], *d[j]));
    const auto mid = dist.begin() + static_cast<ptrdiff_t>((dist.size() - 1) / 2);
    std::nth_element(dist.begin(), mid, dist.end());
    if (*mid < best_median) best = i, best_median = *mid;
  }
  p.descriptor = *d.at(best);
}

}  // namespace hs
