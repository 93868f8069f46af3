#include "mapper/bias_walk_cost.h"

#include <stdexcept>

namespace hs {

BiasWalkCost::BiasWalkCost(const ImuPreintegration& pim) {
  const Eigen::Matrix<double, 6, 1> variance = pim.bias_random_walk_covariance().diagonal();
  if (!(variance.array() > 0.0).all() || !variance.allFinite()) {
    throw std::invalid_argument("BiasWalkCost: bias random-walk covariance is not positive");
  }
  inv_sigma_ = variance.cwiseSqrt().cwiseInverse();
}

bool BiasWalkCost::Evaluate(double const* const* parameters, double* residuals,
                            double** jacobians) const {
  const Eigen::Map<const Eigen::Matrix<double, 6, 1>> b_i(parameters[0] + 3),
      b_j(parameters[1] + 3);
  Eigen::Map<Eigen::Matrix<double, 6, 1>> r(residuals);
  r = inv_sigma_.cwiseProduct(b_j - b_i);
  if (jacobians == nullptr) return true;
  using Jacobian = Eigen::Matrix<double, 6, kSpeedBiasSize, Eigen::RowMajor>;
  for (int k = 0; k < 2; ++k) {
    if (jacobians[k] == nullptr) continue;
    Eigen::Map<Jacobian> J(jacobians[k]);
    J.setZero();
    J.rightCols<6>().diagonal() = (k == 0 ? -1.0 : 1.0) * inv_sigma_;
  }
  return true;
}

}  // namespace hs
