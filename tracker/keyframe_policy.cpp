#include "tracker/keyframe_policy.h"

namespace hs {

double pose_change_norm(const Eigen::Isometry3d& T_w_prev, const Eigen::Isometry3d& T_w_cur) {
  return ((T_w_cur.inverse() * T_w_prev).matrix() - Eigen::Matrix4d::Identity()).norm();
}

double mean_parallax(const std::vector<Eigen::Vector2d>& uv_ref,
                     const std::vector<Eigen::Vector2d>& uv_cur) {
  if (uv_ref.empty() || uv_ref.size() != uv_cur.size()) return 0.0;
  double sum = 0.0;
  for (size_t i = 0; i < uv_ref.size(); ++i) sum += (uv_ref[i] - uv_cur[i]).norm();
  return sum / static_cast<double>(uv_ref.size());
}

KeyframeDecision decide_keyframe(const KeyframePolicyOptions& o, double pose_change,
                                 double parallax_px, int tracked, int64_t since_last_ns) {
  KeyframeDecision d;
  d.pose_change = pose_change;
  d.parallax_px = parallax_px;
  if (tracked < o.min_tracked) {
    d.reason = "tracked " + std::to_string(tracked) + " < N_min " + std::to_string(o.min_tracked);
  } else if (since_last_ns < o.min_interval_ns) {
    return d;
  } else if (pose_change > o.pose_change) {
    d.reason = "pose change";
  } else if (parallax_px > o.parallax_px) {
    d.reason = "parallax";
  } else if (since_last_ns >= o.max_interval_ns) {
    d.reason = "interval";
  } else {
    return d;
  }
  d.is_keyframe = true;
  return d;
}

}  // namespace hs
