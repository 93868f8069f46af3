#pragma once
// Inertial terms of the visual-inertial motion-only optimisation, over the variables
// [x_j (15), x_i (15)] (current state first, previous second; tangent of pose_opt_types.h):
//  - the IMU preintegration residual between x_i and x_j (common/imu/imu_residual.h, evaluated
//    with the previous state's bias), weighted by the inverse preintegration covariance;
//  - the bias random walk [bg_j - bg_i; ba_j - ba_i] over the window;
//  - when x_i is free, the Gaussian prior [Log(R0^T R_i); p_i - p0; v_i - v0; bg_i - bg0;
//    ba_i - ba0] with the previous optimisation's information.
#include <Eigen/Core>

#include "common/imu/preintegration.h"
#include "tracker/pose_opt_state.h"
#include "tracker/pose_opt_types.h"

namespace hs {

using Matrix30d = Eigen::Matrix<double, 30, 30>;
using Vector30d = Eigen::Matrix<double, 30, 1>;

class InertialTerms {
 public:
  // Throws std::invalid_argument when the preintegration does not start at the previous state's
  // time, is empty, or has a singular covariance. `pim` must outlive this object.
  InertialTerms(const ImuPreintegration& pim, const PreviousState& previous,
                const Eigen::Vector3d& g_w);

  // Cost 0.5 * sum of squared Mahalanobis norms at (x_j, x_i); fills the Gauss-Newton system
  // (b = gradient) when H and b are not null. Rows/columns of x_i are zero when it is fixed.
  double linearise(const BodyState& x_j, const BodyState& x_i, Matrix30d* H = nullptr,
                   Vector30d* b = nullptr) const;

  bool previous_fixed() const { return fixed_; }
  const BodyState& previous() const { return previous_; }

 private:
  const ImuPreintegration& pim_;
  BodyState previous_;
  bool fixed_;
  Matrix15d prior_information_;
  Eigen::Vector3d g_w_;
  Matrix9d imu_information_;
  Eigen::Matrix<double, 6, 1> random_walk_information_;  // diagonal
};

}  // namespace hs
