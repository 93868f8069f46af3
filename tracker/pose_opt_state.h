#pragma once
// The navigation state as the optimiser iterates on it (rotation matrix instead of quaternion),
// with the retraction of the tangent convention in pose_opt_types.h.
#include <Eigen/Core>

#include "common/core/types.h"
#include "common/imu/preintegration.h"

namespace hs {

using Vector15d = Eigen::Matrix<double, 15, 1>;

struct BodyState {
  Eigen::Matrix3d R_w_b = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_w_b = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_w = Eigen::Vector3d::Zero();
  ImuBias bias;

  static BodyState from(const NavState& s);
  // `like` supplies the time stamp.
  NavState to_nav_state(const NavState& like) const;

  // this [+] delta for delta = [d_phi, d_p, d_v, d_bg, d_ba]; the pose-only retraction uses
  // the first 6 components.
  BodyState retracted(const Vector15d& delta) const;
  BodyState retracted_pose(const Eigen::Matrix<double, 6, 1>& delta) const;

  bool all_finite() const;
};

}  // namespace hs
