#pragma once
// Preintegrated IMU factor between consecutive keyframes i and j: the 9-dim residual of
// common/imu/imu_residual.h (rotation, velocity, position; bias-corrected to first order with
// keyframe i's biases), whitened by the preintegration covariance. Parameter blocks: pose_i,
// speed_bias_i, pose_j, speed_bias_j (layouts in mapper/pose_manifold.h), and the gravity
// vector g_w (3, shared by all IMU factors; held constant or on a sphere manifold).
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "common/imu/preintegration.h"
#include "mapper/pose_manifold.h"

namespace hs {

class ImuCost
    : public ceres::SizedCostFunction<9, kPoseSize, kSpeedBiasSize, kPoseSize, kSpeedBiasSize, 3> {
 public:
  // Throws std::invalid_argument when the preintegration is empty or its covariance singular.
  explicit ImuCost(const ImuPreintegration& pim);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  ImuPreintegration pim_;
  Matrix9d sqrt_information_;  // S with S^T S = covariance^-1
};

}  // namespace hs
