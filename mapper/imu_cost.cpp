#include "mapper/imu_cost.h"

#include <Eigen/Cholesky>
#include <stdexcept>

#include "common/imu/imu_residual.h"

namespace hs {

ImuCost::ImuCost(const ImuPreintegration& pim) : pim_(pim) {
  if (pim.t1_ns() <= pim.t0_ns()) throw std::invalid_argument("ImuCost: empty preintegration");
  // covariance = L L^T, so S = L^-1 whitens: |S r|^2 = r^T covariance^-1 r.
  const Eigen::LLT<Matrix9d> llt(pim.covariance());
  if (llt.info() != Eigen::Success) {
    throw std::invalid_argument("ImuCost: preintegration covariance is not positive definite");
  }
  sqrt_information_ = llt.matrixL().solve(Matrix9d::Identity());
}

bool ImuCost::Evaluate(double const* const* parameters, double* residuals,
                       double** jacobians) const {
  const double* pose_i = parameters[0];
  const double* pose_j = parameters[2];
  const Eigen::Map<const Eigen::Vector3d> v_i(parameters[1]), v_j(parameters[3]);
  const ImuBias bias_i{Eigen::Map<const Eigen::Vector3d>(parameters[1] + 3),
                       Eigen::Map<const Eigen::Vector3d>(parameters[1] + 6)};
  const Eigen::Map<const Eigen::Vector3d> g_w(parameters[4]);
  ImuResidualJacobians J;
  const Vector9d r = imu_residual(pim_, pose_q_w_b(pose_i).toRotationMatrix(), pose_p_w_b(pose_i),
                                  v_i, pose_q_w_b(pose_j).toRotationMatrix(), pose_p_w_b(pose_j),
                                  v_j, bias_i, g_w, jacobians != nullptr ? &J : nullptr);
  Eigen::Map<Vector9d> whitened(residuals);
  whitened = sqrt_information_ * r;
  if (jacobians == nullptr) return true;

  using PoseJacobian = Eigen::Matrix<double, 9, kPoseSize, Eigen::RowMajor>;
  using SpeedBiasJacobian = Eigen::Matrix<double, 9, kSpeedBiasSize, Eigen::RowMajor>;
  const auto fill_pose = [&](const Matrix93d& J_R, const Matrix93d& J_p, double* out) {
    Eigen::Map<PoseJacobian> Jp(out);
    Jp.leftCols<3>() = sqrt_information_ * J_R;
    Jp.col(3).setZero();
    Jp.rightCols<3>() = sqrt_information_ * J_p;
  };
  if (jacobians[0] != nullptr) fill_pose(J.R_i, J.p_i, jacobians[0]);
  if (jacobians[2] != nullptr) fill_pose(J.R_j, J.p_j, jacobians[2]);
  if (jacobians[1] != nullptr) {
    Eigen::Map<SpeedBiasJacobian> Jsb(jacobians[1]);
    Jsb << sqrt_information_ * J.v_i, sqrt_information_ * J.bg, sqrt_information_ * J.ba;
  }
  if (jacobians[3] != nullptr) {
    // The residual uses keyframe i's biases only.
    Eigen::Map<SpeedBiasJacobian> Jsb(jacobians[3]);
    Jsb.setZero();
    Jsb.leftCols<3>() = sqrt_information_ * J.v_j;
  }
  if (jacobians[4] != nullptr) {
    // g enters as -R_i^T g dt (velocity) and -R_i^T g dt^2 / 2 (position).
    const double dt = pim_.dt_s();
    const Eigen::Matrix3d Rt = pose_q_w_b(parameters[0]).toRotationMatrix().transpose();
    Matrix93d J_g = Matrix93d::Zero();
    J_g.middleRows<3>(3) = -dt * Rt;
    J_g.bottomRows<3>() = -0.5 * dt * dt * Rt;
    Eigen::Map<Eigen::Matrix<double, 9, 3, Eigen::RowMajor>> Jg(jacobians[4]);
    Jg = sqrt_information_ * J_g;
  }
  return true;
}

}  // namespace hs
