#include "tracker/local_map.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace hs {

MapPoint* LocalMap::point(int64_t id) {
  const auto it = points_.find(id);
  return it == points_.end() ? nullptr : &it->second;
}

std::shared_ptr<Keyframe> LocalMap::keyframe(int64_t id) const {
  for (const auto* list : {&window_, &database_})
    for (const auto& kf : *list)
      if (kf->id == id) return kf;
  return nullptr;
}

bool LocalMap::in_window_after_next_keyframe(int64_t id) const {
  if (window_full() && window_.front()->id == id) return false;
  return std::any_of(window_.begin(), window_.end(), [id](const auto& kf) { return kf->id == id; });
}

void LocalMap::add_keyframe(std::shared_ptr<Keyframe> keyframe) {
  const bool retire = window_full();
  window_.push_back(std::move(keyframe));
  if (!retire) return;
  retire_oldest();
  drop_unreferenced_points();
}

void LocalMap::retire_window() {
  while (!window_.empty()) retire_oldest();
  points_.clear();
}

void LocalMap::retire_oldest() {
  // The keyframe leaving the window keeps only what relocalisation needs: thumbnail,
  // features, pose and its points' positions.
  std::shared_ptr<Keyframe> old = window_.front();
  window_.pop_front();
  old->frozen_p_w.assign(old->point_ids.size(), Eigen::Vector3d::Constant(NAN));
  for (size_t i = 0; i < old->point_ids.size(); ++i)
    if (const MapPoint* p = point(old->point_ids[i])) old->frozen_p_w[i] = p->p_w;
  old->pyramid.levels.clear();
  old->imu.clear();
  database_.push_back(old);
  if (static_cast<int>(database_.size()) > options_.max_database_keyframes) database_.pop_front();
}

void LocalMap::drop_unreferenced_points() {
  std::unordered_set<int64_t> referenced;
  for (const auto& kf : window_)
    for (int64_t id : kf->point_ids)
      if (id >= 0) referenced.insert(id);
  for (auto it = points_.begin(); it != points_.end();)
    it = referenced.count(it->first) ? std::next(it) : points_.erase(it);
}

std::vector<std::optional<Eigen::Vector3d>> LocalMap::point_positions(const Keyframe& kf) const {
  std::vector<std::optional<Eigen::Vector3d>> out(kf.point_ids.size());
  for (size_t i = 0; i < kf.point_ids.size(); ++i) {
    if (!kf.frozen_p_w.empty()) {
      if (kf.frozen_p_w[i].allFinite()) out[i] = kf.frozen_p_w[i];
    } else if (const auto it = points_.find(kf.point_ids[i]); it != points_.end()) {
      out[i] = it->second.p_w;
    }
  }
  return out;
}

Eigen::Isometry3d WorldSimilarity::camera(const Eigen::Isometry3d& T_w_c) const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R_new_old * T_w_c.linear();
  T.translation() = point(T_w_c.translation());
  return T;
}

NavState WorldSimilarity::body(const NavState& x, const Eigen::Isometry3d& T_b_c) const {
  NavState y = x;
  y.set_T_w_b(camera(x.T_w_b() * T_b_c) * T_b_c.inverse());
  y.v_w = scale * (R_new_old * x.v_w);
  return y;
}

void LocalMap::transform_world(const WorldSimilarity& S, const Eigen::Isometry3d& T_b_c0) {
  for (auto& [id, p] : points_) {
    p.p_w = S.point(p.p_w);
    p.n_w = S.R_new_old * p.n_w;
  }
  for (const auto* list : {&window_, &database_})
    for (const auto& kf : *list) {
      kf->T_w_c0 = S.camera(kf->T_w_c0);
      kf->state = S.body(kf->state, T_b_c0);
      for (Eigen::Vector3d& p_w : kf->frozen_p_w) p_w = S.point(p_w);
    }
}

void LocalMap::clear() {
  window_.clear();
  database_.clear();
  points_.clear();
}

}  // namespace hs
