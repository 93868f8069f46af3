// Tracker::apply: mapper corrections of the tracker's map and state.
#include <algorithm>
#include <cmath>
#include <memory>

#include "tracker/tracker.h"

namespace hs {

CorrectionResult Tracker::apply(const MapCorrection& c) {
  CorrectionResult out;
  const auto ignore = [&](const std::string& why) {
    ++counters_.corrections_ignored;
    out.message = "map correction " + std::to_string(c.seq) + " ignored: " + why;
    return out;
  };
  if (!last_ || state_ == TrackState::kInitialising || bootstrap_)
    return ignore("the tracker is initialising");
  if (c.map_id != map_id_)
    return ignore("it is for map id " + std::to_string(c.map_id) + ", the tracker is on " +
                  std::to_string(map_id_));
  // The newest corrected keyframe the tracker still has anchors the current state: the frames
  // since were tracked against the map as it was around that keyframe.
  const KeyframeCorrection* anchor = nullptr;
  std::shared_ptr<Keyframe> anchor_kf;
  for (const KeyframeCorrection& k : c.keyframes) {
    if (anchor && k.state.t_ns <= anchor->state.t_ns) continue;
    if (auto kf = map_.keyframe(k.id); kf && kf->state.t_ns == k.state.t_ns) {
      anchor = &k;
      anchor_kf = std::move(kf);
    }
  }
  if (!anchor) return ignore("it names no keyframe the tracker still has");
  const bool has_gravity = !c.g_w.isZero();
  if (has_gravity) {
    const double tilt = gravity_tilt_rad(c.g_w);
    const double magnitude_error = std::abs(c.g_w.norm() / kGravityMagnitude - 1.0);
    if (!(tilt <= options_.corrections.max_gravity_tilt_rad) ||
        !(magnitude_error <= options_.corrections.max_gravity_magnitude_error))
      return ignore("its gravity is " + std::to_string(tilt * 180.0 / M_PI) + " deg off -z and " +
                    std::to_string(c.g_w.norm()) + " m/s^2");
  }
  const Eigen::Isometry3d delta = anchor->state.T_w_b() * anchor_kf->state.T_w_b().inverse();

  for (const KeyframeCorrection& k : c.keyframes) {
    const std::shared_ptr<Keyframe> kf = map_.keyframe(k.id);
    if (!kf || kf->state.t_ns != k.state.t_ns) continue;
    kf->state = k.state;
    kf->T_w_c0 = T_w_c0(k.state);
  }
  for (const PointCorrection& p : c.points)
    if (MapPoint* point = map_.point(p.id)) point->p_w = p.p_w;
  for (int64_t id : c.removed_points) map_.remove_point(id);

  NavState& nav = last_->nav;
  const Eigen::Vector3d p_before = nav.p_w_b;
  if (anchor->state.t_ns == last_->t_ns) {
    nav = anchor->state;  // the corrected keyframe is the last frame: its velocity too
  } else {
    nav.p_w_b = delta * nav.p_w_b;
    nav.q_w_b = Eigen::Quaterniond(delta.linear() * nav.q_w_b.toRotationMatrix()).normalized();
    nav.v_w = delta.linear() * nav.v_w;
    nav.gyro_bias = anchor->state.gyro_bias;
    nav.accel_bias = anchor->state.accel_bias;
  }
  last_keyframe_T_w_c_ = delta * last_keyframe_T_w_c_;
  if (has_gravity) {
    optimizer_.set_gravity(c.g_w);
  }
  ++counters_.corrections_applied;
  counters_.last_correction_lag_ms = (last_->t_ns - anchor->state.t_ns) / 1'000'000;
  counters_.max_correction_lag_ms =
      std::max(counters_.max_correction_lag_ms, counters_.last_correction_lag_ms);
  out.applied = true;
  out.shift_m = (nav.p_w_b - p_before).norm();
  out.shift_rad = Eigen::AngleAxisd(delta.linear()).angle();
  if (out.shift_m > options_.corrections.max_silent_translation_m ||
      out.shift_rad > options_.corrections.max_silent_rotation_rad) {
    map_id_ = new_map_id();
    ++counters_.correction_jumps;
    out.message = "map correction " + std::to_string(c.seq) + " moved the pose " +
                  std::to_string(out.shift_m) + " m / " +
                  std::to_string(out.shift_rad * 180.0 / M_PI) + " deg: map id now " +
                  std::to_string(map_id_);
  }
  return out;
}

}  // namespace hs
