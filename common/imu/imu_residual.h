#pragma once
// State prediction through a preintegration (paper Eq. 16: T_j = T_i * T_ij^IMU) and the 9-dim
// preintegration residual with analytic Jacobians, shared by the tracker's IMU prior and the
// mapper's inertial factors.
//
// Perturbation conventions of the Jacobians: rotations on the right, R <- R * Exp(d); positions,
// velocities and biases additively in their own frame (world for p, v).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "common/core/types.h"
#include "common/imu/preintegration.h"

namespace hs {

constexpr double kGravityMagnitude = 9.81;  // m/s^2
inline Eigen::Vector3d default_gravity_w() {
  return {0.0, 0.0, -kGravityMagnitude};
}
// Angle between a gravity vector and the world's -z (radians).
inline double gravity_tilt_rad(const Eigen::Vector3d& g_w) {
  return std::acos(std::clamp(-g_w.normalized().z(), -1.0, 1.0));
}

// The state at pim.t1_ns() from the state at pim.t0_ns() (whose biases are used, through the
// first-order bias correction, and carried over unchanged).
NavState predict(const NavState& state_i, const ImuPreintegration& pim,
                 const Eigen::Vector3d& g_w = default_gravity_w());

using Matrix93d = Eigen::Matrix<double, 9, 3>;

// Derivatives of the residual w.r.t. each 3-dim state block.
struct ImuResidualJacobians {
  Matrix93d R_i, p_i, v_i;
  Matrix93d R_j, p_j, v_j;
  Matrix93d bg, ba;  // w.r.t. bias_i
};

// r = [Log(dR^T R_i^T R_j);
//      R_i^T (v_j - v_i - g dt) - dv;
//      R_i^T (p_j - p_i - v_i dt - g dt^2 / 2) - dp]
// with (dR, dv, dp) = pim.corrected(bias_i). Zero for states consistent with the IMU signal.
// Fills `jacobians` when it is not null.
Vector9d imu_residual(const ImuPreintegration& pim, const Eigen::Matrix3d& R_w_bi,
                      const Eigen::Vector3d& p_w_bi, const Eigen::Vector3d& v_w_i,
                      const Eigen::Matrix3d& R_w_bj, const Eigen::Vector3d& p_w_bj,
                      const Eigen::Vector3d& v_w_j, const ImuBias& bias_i,
                      const Eigen::Vector3d& g_w, ImuResidualJacobians* jacobians = nullptr);

}  // namespace hs
