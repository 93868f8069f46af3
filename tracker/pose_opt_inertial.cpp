#include "tracker/pose_opt_inertial.h"

#include <Eigen/Cholesky>
#include <stdexcept>

#include "common/imu/imu_residual.h"
#include "common/imu/so3.h"

namespace hs {

InertialTerms::InertialTerms(const ImuPreintegration& pim, const PreviousState& previous,
                             const Eigen::Vector3d& g_w)
    : pim_(pim),
      previous_(BodyState::from(previous.state)),
      fixed_(previous.fixed),
      prior_information_(0.5 * (previous.information + previous.information.transpose())),
      g_w_(g_w) {
  if (pim.t0_ns() != previous.state.t_ns) {
    throw std::invalid_argument(
        "InertialTerms: the preintegration does not start at the "
        "previous state's time");
  }
  if (pim.t1_ns() <= pim.t0_ns())
    throw std::invalid_argument("InertialTerms: empty preintegration");
  const Eigen::LLT<Matrix9d> llt(pim.covariance());
  const Eigen::Matrix<double, 6, 1> rw_var = pim.bias_random_walk_covariance().diagonal();
  if (llt.info() != Eigen::Success || !(rw_var.array() > 0.0).all()) {
    throw std::invalid_argument("InertialTerms: singular preintegration or bias covariance");
  }
  imu_information_ = llt.solve(Matrix9d::Identity());
  imu_information_ = 0.5 * (imu_information_ + imu_information_.transpose()).eval();
  random_walk_information_ = rw_var.cwiseInverse();
  if (!fixed_ && !prior_information_.allFinite()) {
    throw std::invalid_argument("InertialTerms: non-finite prior information");
  }
}

double InertialTerms::linearise(const BodyState& x_j, const BodyState& x_i, Matrix30d* H,
                                Vector30d* b) const {
  ImuResidualJacobians J_imu;
  const Vector9d r_imu = imu_residual(pim_, x_i.R_w_b, x_i.p_w_b, x_i.v_w, x_j.R_w_b, x_j.p_w_b,
                                      x_j.v_w, x_i.bias, g_w_, H != nullptr ? &J_imu : nullptr);
  Eigen::Matrix<double, 6, 1> r_rw;
  r_rw << x_j.bias.gyro - x_i.bias.gyro, x_j.bias.accel - x_i.bias.accel;
  Vector15d r_prior = Vector15d::Zero();
  if (!fixed_) {
    r_prior << so3::log(previous_.R_w_b.transpose() * x_i.R_w_b), x_i.p_w_b - previous_.p_w_b,
        x_i.v_w - previous_.v_w, x_i.bias.gyro - previous_.bias.gyro,
        x_i.bias.accel - previous_.bias.accel;
  }
  const double cost = 0.5 * (r_imu.dot(imu_information_ * r_imu) +
                             r_rw.dot(random_walk_information_.cwiseProduct(r_rw)) +
                             r_prior.dot(prior_information_ * r_prior));
  if (H == nullptr || b == nullptr) return cost;

  // The IMU residual depends on (R, p, v) of x_j and on all of x_i: fill only those blocks.
  H->setZero();
  b->setZero();
  Eigen::Matrix<double, 9, 9> J_j;
  J_j << J_imu.R_j, J_imu.p_j, J_imu.v_j;
  const Eigen::Matrix<double, 9, 9> WJ_j = imu_information_ * J_j;
  H->topLeftCorner<9, 9>().noalias() = J_j.transpose().lazyProduct(WJ_j);
  b->head<9>().noalias() = WJ_j.transpose() * r_imu;
  if (!fixed_) {
    Eigen::Matrix<double, 9, 15> J_i;
    J_i << J_imu.R_i, J_imu.p_i, J_imu.v_i, J_imu.bg, J_imu.ba;
    const Eigen::Matrix<double, 9, 15> WJ_i = imu_information_ * J_i;
    H->block<15, 15>(15, 15).noalias() = J_i.transpose().lazyProduct(WJ_i);
    H->block<15, 9>(15, 0).noalias() = J_i.transpose().lazyProduct(WJ_j);
    H->block<9, 15>(0, 15) = H->block<15, 9>(15, 0).transpose();
    b->tail<15>().noalias() = WJ_i.transpose() * r_imu;
  }

  // Random walk: d r_rw / d bias_j = I, d r_rw / d bias_i = -I.
  for (int k = 0; k < 6; ++k) {
    const double w = random_walk_information_[k];
    const int j = 9 + k, i = 24 + k;
    (*H)(j, j) += w;
    (*b)(j) += w * r_rw[k];
    if (fixed_) continue;
    (*H)(i, i) += w;
    (*H)(i, j) -= w;
    (*H)(j, i) -= w;
    (*b)(i) -= w * r_rw[k];
  }

  if (!fixed_) {
    // J_prior = blockdiag(M, I) with M = Jr^-1(r_R): J^T L J and J^T L r only change the
    // rotation rows and columns of L.
    const Eigen::Matrix3d M = so3::right_jacobian_inverse(r_prior.head<3>());
    Matrix15d JtLJ = prior_information_;
    JtLJ.topRows<3>() = M.transpose() * JtLJ.topRows<3>();
    JtLJ.leftCols<3>() = JtLJ.leftCols<3>() * M;
    H->bottomRightCorner<15, 15>() += JtLJ;
    Vector15d Lr = prior_information_ * r_prior;
    Lr.head<3>() = M.transpose() * Lr.head<3>();
    b->tail<15>() += Lr;
  }
  return cost;
}

}  // namespace hs
