#pragma once
// Parameter blocks of the local bundle adjustment and the manifold of the pose block.
//
// Pose block (7 doubles): [qx, qy, qz, qw, px, py, pz], i.e. q_w_b in Eigen's coefficient
// order, then p_w_b. Its tangent (6) is [d_phi, d_p] as in tracker/pose_opt_types.h:
//   R_w_b <- R_w_b * Exp(d_phi),  p_w_b <- p_w_b + d_p.
// Speed-bias block (9 doubles): [v_w, gyro_bias, accel_bias], a plain vector space.
//
// The cost functions write their derivatives w.r.t. the pose *tangent* into the pose block's
// Jacobian (rotation in columns 0-2, column 3 zero, position in columns 4-6) and
// PlusJacobian() is the matching selection matrix, so Ceres' product J * PlusJacobian is the
// tangent Jacobian without differentiating through the quaternion. The pair is only valid
// together: ceres::GradientChecker would reject it, so the tests compare against finite
// differences in the tangent instead.
#include <ceres/manifold.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/core/types.h"

namespace hs {

constexpr int kPoseSize = 7;
constexpr int kPoseTangentSize = 6;
constexpr int kSpeedBiasSize = 9;

class PoseManifold : public ceres::Manifold {
 public:
  int AmbientSize() const override { return kPoseSize; }
  int TangentSize() const override { return kPoseTangentSize; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

// Views of a pose block.
inline Eigen::Map<const Eigen::Quaterniond> pose_q_w_b(const double* pose) {
  return Eigen::Map<const Eigen::Quaterniond>(pose);
}
inline Eigen::Map<const Eigen::Vector3d> pose_p_w_b(const double* pose) {
  return Eigen::Map<const Eigen::Vector3d>(pose + 4);
}

// NavState <-> blocks.
void state_to_blocks(const NavState& state, double* pose, double* speed_bias);
void blocks_to_state(const double* pose, const double* speed_bias, NavState* state);

}  // namespace hs
