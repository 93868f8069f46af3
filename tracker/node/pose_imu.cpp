#include "tracker/node/pose_imu.h"

#include <vector>

#include "common/imu/imu_residual.h"
#include "common/imu/preintegration.h"

namespace hs {

void PoseImuPropagator::add(const ImuSample& sample) {
  if (!samples_.empty() && sample.t_ns <= samples_.back().t_ns) return;
  samples_.push_back(sample);
  trim();
}

void PoseImuPropagator::set_anchor(const PoseAnchor& anchor) {
  anchor_ = anchor;
  trim();
}

void PoseImuPropagator::trim() {
  if (samples_.empty()) return;
  // Keep the last sample at or before the anchor (it interpolates the window start), and never
  // more than keep_ns of history.
  int64_t from = samples_.back().t_ns - keep_ns_;
  if (anchor_ && anchor_->nav.t_ns > from) from = anchor_->nav.t_ns;
  while (samples_.size() > 1 && samples_[1].t_ns <= from) samples_.pop_front();
}

std::optional<NavState> PoseImuPropagator::propagate(int64_t t_ns) const {
  // Beyond keep_ns without a new frame, IMU-only dead reckoning is not worth publishing.
  if (!anchor_ || t_ns < anchor_->nav.t_ns || t_ns - anchor_->nav.t_ns > keep_ns_)
    return std::nullopt;
  ImuBias bias;
  bias.gyro = anchor_->nav.gyro_bias;
  bias.accel = anchor_->nav.accel_bias;
  const std::vector<ImuSample> window(samples_.begin(), samples_.end());
  const ImuPreintegration pim = preintegrate(window, anchor_->nav.t_ns, t_ns, bias, imu_);
  NavState s = predict(anchor_->nav, pim, anchor_->g_w);
  s.t_ns = t_ns;
  return s;
}

}  // namespace hs
