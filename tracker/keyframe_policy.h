#pragma once
// Keyframe selection of the paper (Sec. 3.1.4): a frame becomes a keyframe when the pose
// changed enough since the previous frame (Eq. 13), the tracked features moved enough (Eq. 14),
// or too few features are still tracked (Eq. 15). Two guards bound the rate: a minimum
// spacing, and a maximum interval so that the map keeps up during slow motion.
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace hs {

struct KeyframePolicyOptions {
  double pose_change = 0.5;   // tau_T: || T_t^-1 T_{t-1} - I ||_F, Eq. 13
  double parallax_px = 25.0;  // tau_p: mean rotation-compensated pixel motion since the KF, Eq. 14
  int min_tracked = 80;       // N_min of Eq. 15
  int64_t min_interval_ns = 100'000'000;
  int64_t max_interval_ns = 1'000'000'000;
};

struct KeyframeDecision {
  bool is_keyframe = false;
  std::string reason;  // which criterion fired
  double pose_change = 0.0;
  double parallax_px = 0.0;
};

// Eq. 13: Frobenius norm of (T_t^-1 T_{t-1} - I), translation in metres.
double pose_change_norm(const Eigen::Isometry3d& T_w_prev, const Eigen::Isometry3d& T_w_cur);

// Eq. 14: mean displacement between matched pixel pairs.
double mean_parallax(const std::vector<Eigen::Vector2d>& uv_ref,
                     const std::vector<Eigen::Vector2d>& uv_cur);

KeyframeDecision decide_keyframe(const KeyframePolicyOptions& options, double pose_change,
                                 double parallax_px, int tracked, int64_t since_last_keyframe_ns);

}  // namespace hs
