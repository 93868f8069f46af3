#pragma once
// Bias random walk between consecutive keyframes: r = W (b_j - b_i) for b = [gyro, accel],
// W = diag(1 / sigma) from the preintegration window's random-walk covariance. Parameter
// blocks: speed_bias_i, speed_bias_j (mapper/pose_manifold.h).
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "common/imu/preintegration.h"
#include "mapper/pose_manifold.h"

namespace hs {

class BiasWalkCost : public ceres::SizedCostFunction<6, kSpeedBiasSize, kSpeedBiasSize> {
 public:
  // Throws std::invalid_argument when the random-walk covariance is not positive.
  explicit BiasWalkCost(const ImuPreintegration& pim);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  Eigen::Matrix<double, 6, 1> inv_sigma_;
};

}  // namespace hs
