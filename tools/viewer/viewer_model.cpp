#include "tools/viewer/viewer_model.h"

#include <algorithm>
#include <cmath>

namespace hs {
namespace {

// Heading of the body x axis in the x-y plane, from a (w, x, y, z) quaternion.
double yaw_of(const double q[4]) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  return std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
}

Eigen::Vector3d vec(const double p[3]) {
  return Eigen::Vector3d(p[0], p[1], p[2]);
}

}  // namespace

ViewerModel::ViewerModel(size_t image_history, size_t timing_window)
    : image_history_(std::max<size_t>(1, image_history)),
      timing_window_(std::max<size_t>(1, timing_window)) {}

void ViewerModel::on_image(int64_t t_ns, cv::Mat cam0) {
  images_.emplace_back(t_ns, std::move(cam0));
  while (images_.size() > image_history_) images_.pop_front();
  // A status that came before its image (another host's clock of arrival): match it now.
  for (auto it = pending_.begin(); it != pending_.end(); ++it) {
    if (it->t_ns != t_ns) continue;
    frame_ = FrameView{images_.back().second, *it};
    pending_.erase(pending_.begin(), it + 1);
    break;
  }
  ++version_;
}

void ViewerModel::on_status(const hsslam::tracker_status_t& status) {
  status_ = status;
  if (first_t_ns_ == 0) first_t_ns_ = status.t_ns;
  timing_.push_back(status);
  while (timing_.size() > timing_window_) timing_.pop_front();
  const auto image = std::find_if(images_.rbegin(), images_.rend(),
                                  [&](const auto& im) { return im.first == status.t_ns; });
  if (image != images_.rend()) {
    frame_ = FrameView{image->second, status};
  } else {
    pending_.push_back(status);
    while (pending_.size() > image_history_) pending_.pop_front();
  }
  ++version_;
}

void ViewerModel::on_pose(const hsslam::odometry_t& pose) {
  if (first_t_ns_ == 0) first_t_ns_ = pose.t_ns;
  TrajectoryPoint p;
  p.t_ns = pose.t_ns;
  p.map_id = pose.map_id;
  p.state = pose.state;
  p.p_w = vec(pose.p_w_b);
  p.yaw = yaw_of(pose.q_w_b);
  trajectory_.push_back(p);
  ++version_;
}

void ViewerModel::on_keyframe(const hsslam::keyframe_t& kf) {
  KeyframeMark& mark = keyframes_[kf.pose.id];
  mark.map_id = kf.map_id;
  mark.p_w = vec(kf.pose.p_w_b);
  for (const hsslam::map_point_t& p : kf.points) points_[p.id] = vec(p.p_w);
  ++version_;
}

void ViewerModel::on_map_update(const hsslam::map_update_t& update) {
  ++map_updates_;
  for (const hsslam::keyframe_pose_t& k : update.keyframes) {
    const auto it = keyframes_.find(k.id);
    if (it == keyframes_.end()) continue;
    it->second.p_w = vec(k.p_w_b);
    it->second.corrected = true;
  }
  for (const hsslam::map_point_t& p : update.points) {
    const auto it = points_.find(p.id);
    if (it != points_.end()) it->second = vec(p.p_w);
  }
  for (const int64_t id : update.removed_point_ids) points_.erase(id);
  ++version_;
}

void ViewerModel::on_bad_message(const std::string& what) {
  ++bad_messages_;
  last_bad_ = what;
  ++version_;
}

TimingSummary ViewerModel::timing() const {
  TimingSummary s;
  std::vector<std::string> order;
  std::map<std::string, double> sum;
  double kf_sum = 0, other_sum = 0;
  for (const hsslam::tracker_status_t& st : timing_) {
    if (st.total_ms <= 0) continue;  // not tracked (initialising, rejected)
    ++s.frames;
    s.mean_ms += st.total_ms;
    s.max_ms = std::max(s.max_ms, static_cast<double>(st.total_ms));
    (st.is_keyframe ? kf_sum : other_sum) += st.total_ms;
    s.keyframes += st.is_keyframe;
    for (size_t i = 0; i < st.stage_names.size() && i < st.stage_ms.size(); ++i) {
      if (!sum.count(st.stage_names[i])) order.push_back(st.stage_names[i]);
      sum[st.stage_names[i]] += st.stage_ms[i];
    }
  }
  if (s.frames == 0) return s;
  s.mean_ms /= s.frames;
  if (s.keyframes > 0) s.mean_keyframe_ms = kf_sum / s.keyframes;
  if (s.frames > s.keyframes) s.mean_other_ms = other_sum / (s.frames - s.keyframes);
  for (const std::string& name : order) s.mean_stage_ms.emplace_back(name, sum[name] / s.frames);
  return s;
}

}  // namespace hs
