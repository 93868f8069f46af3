#pragma once
// POSE_IMU on the receive side: the latest tracked state (the anchor, handed over by the
// tracking thread) propagated with the IMU samples received since, so the rate stays the IMU
// rate while a frame is being tracked. Owned by one thread (the LCM receive thread).
#include <cstdint>
#include <deque>
#include <optional>

#include "common/core/types.h"
#include "common/imu/imu_options.h"
#include "common/imu/imu_residual.h"
#include "tracker/tracker_types.h"

namespace hs {

struct PoseAnchor {
  NavState nav;  // the tracked state of a frame
  TrackState state = TrackState::kTracking;
  int32_t map_id = 0;
  float quality = 0.0f;
  Eigen::Vector3d g_w = default_gravity_w();  // the tracker's at the anchor
};

class PoseImuPropagator {
 public:
  // `keep_ns`: the most IMU history kept, and how far past its anchor a state is propagated.
  PoseImuPropagator(const ImuOptions& imu, int64_t keep_ns) : imu_(imu), keep_ns_(keep_ns) {}

  // Samples not after the newest one are ignored (the tracker counts bad IMU input).
  void add(const ImuSample& sample);
  // Replaces the anchor and forgets the samples it no longer needs.
  void set_anchor(const PoseAnchor& anchor);
  const std::optional<PoseAnchor>& anchor() const { return anchor_; }

  // The anchor state propagated to t_ns (body state, predict() of common/imu/imu_residual.h);
  // nullopt without an anchor, before it, or more than keep_ns after it.
  std::optional<NavState> propagate(int64_t t_ns) const;
  size_t buffered() const { return samples_.size(); }

 private:
  void trim();

  ImuOptions imu_;
  int64_t keep_ns_;
  std::deque<ImuSample> samples_;
  std::optional<PoseAnchor> anchor_;
};

}  // namespace hs
