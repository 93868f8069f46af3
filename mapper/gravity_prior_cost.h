#pragma once
// Prior on the gravity direction: r = (g - g0) / (|g0| sigma), for a gravity block on a sphere
// of radius |g0|, where a small rotation by theta moves g by |g0| theta.
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

namespace hs {

class GravityPriorCost : public ceres::SizedCostFunction<3, 3> {
 public:
  GravityPriorCost(const Eigen::Vector3d& g0, double sigma_rad)
      : g0_(g0), inv_sigma_(1.0 / (g0.norm() * sigma_rad)) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    Eigen::Map<Eigen::Vector3d> r(residuals);
    r = inv_sigma_ * (Eigen::Map<const Eigen::Vector3d>(parameters[0]) - g0_);
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> J(jacobians[0]);
      J = inv_sigma_ * Eigen::Matrix3d::Identity();
    }
    return true;
  }

 private:
  Eigen::Vector3d g0_;
  double inv_sigma_;
};

}  // namespace hs
