#include "mapper/reprojection_cost.h"

namespace hs {

RigCamera::RigCamera(const CameraCalib& calib)
    : K(calib.intrinsics),
      max_radius2(calib.intrinsics.max_valid_radius2()),
      R_c_b(calib.T_b_c.linear().transpose()),
      t_c_b(-R_c_b * calib.T_b_c.translation()) {}

ReprojectionCost::ReprojectionCost(const RigCamera& camera, const Eigen::Vector2d& uv,
                                   double sigma_px, double min_depth_m)
    : camera_(&camera), uv_(uv), inv_sigma_(1.0 / sigma_px), min_depth_m_(min_depth_m) {}

bool ReprojectionCost::Evaluate(double const* const* parameters, double* residuals,
                                double** jacobians) const {
  const Eigen::Matrix3d R_w_b = pose_q_w_b(parameters[0]).toRotationMatrix();
  const Eigen::Map<const Eigen::Vector3d> p_w(parameters[1]);
  const Eigen::Vector3d p_b = R_w_b.transpose() * (p_w - pose_p_w_b(parameters[0]));
  const Eigen::Vector3d p_c = camera_->R_c_b * p_b + camera_->t_c_b;
  if (!(p_c.z() >= min_depth_m_)) return false;
  const double inv_z = 1.0 / p_c.z();
  const Eigen::Vector2d xy = p_c.head<2>() * inv_z;
  if (!(xy.squaredNorm() < camera_->max_radius2)) return false;
  const PinholeRadtan& K = camera_->K;
  const Eigen::Vector2d d = K.distort(xy);
  Eigen::Map<Eigen::Vector2d> r(residuals);
  r = inv_sigma_ * Eigen::Vector2d(K.fx * d.x() + K.cx - uv_.x(), K.fy * d.y() + K.cy - uv_.y());
  if (jacobians == nullptr) return true;

  // d r / d p_c = diag(f) * d distort / d xy * d xy / d p_c, whitened.
  const Eigen::Matrix2d Jd =
      inv_sigma_ * Eigen::Vector2d(K.fx, K.fy).asDiagonal() * K.distort_jacobian(xy);
  Eigen::Matrix<double, 2, 3> J_pc;
  J_pc << Jd * inv_z, -inv_z * (Jd * xy);
  const Eigen::Matrix<double, 2, 3> A = J_pc * camera_->R_c_b;  // d r / d p_b
  const Eigen::Matrix<double, 2, 3> J_pw = A * R_w_b.transpose();
  if (jacobians[0] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 2, kPoseSize, Eigen::RowMajor>> J(jacobians[0]);
    // A * hat(p_b): row k is (A_k x p_b)^T.
    for (int k = 0; k < 2; ++k) J.block<1, 3>(k, 0) = A.row(k).cross(p_b.transpose());
    J.col(3).setZero();
    J.rightCols<3>() = -J_pw;
  }
  if (jacobians[1] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> J(jacobians[1]);
    J = J_pw;
  }
  return true;
}

}  // namespace hs
