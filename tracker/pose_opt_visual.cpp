#include "tracker/pose_opt_visual.h"

#include <cmath>
#include <limits>

namespace hs {

CameraView::CameraView(const CameraCalib& camera, double max_radius2, const Eigen::Matrix3d& R_w_b,
                       const Eigen::Vector3d& p_w_b)
    : K_(camera.intrinsics), max_radius2_(max_radius2), p_w_b_(p_w_b) {
  const Eigen::Isometry3d T_c_b = camera.T_b_c.inverse();
  R_c_b_ = T_c_b.linear();
  R_b_w_ = R_w_b.transpose();
  R_c_w_ = R_c_b_ * R_b_w_;
  t_c_w_ = T_c_b.translation() - R_c_w_ * p_w_b;
}

bool CameraView::residual(const Eigen::Vector3d& p_w, const Eigen::Vector2d& uv, double min_depth_m,
                          Eigen::Vector2d* r, Matrix26d* J) const {
  const Eigen::Vector3d p_c = R_c_w_ * p_w + t_c_w_;
  if (!(p_c.z() >= min_depth_m)) return false;
  const double inv_z = 1.0 / p_c.z();
  const Eigen::Vector2d xy = p_c.head<2>() * inv_z;
  if (!(xy.squaredNorm() < max_radius2_)) return false;
  const Eigen::Vector2d d = K_.distort(xy);
  *r = Eigen::Vector2d(K_.fx * d.x() + K_.cx - uv.x(), K_.fy * d.y() + K_.cy - uv.y());
  if (J == nullptr) return true;
  // d pixel / d p_c = diag(f) * d distort / d xy * d xy / d p_c.
  const Eigen::Matrix2d Jd = Eigen::Vector2d(K_.fx, K_.fy).asDiagonal() * K_.distort_jacobian(xy);
  Eigen::Matrix<double, 2, 3> J_pc;
  J_pc << Jd * inv_z, -inv_z * (Jd * xy);
  const Eigen::Vector3d p_b = R_b_w_ * (p_w - p_w_b_);
  const Eigen::Matrix<double, 2, 3> A = J_pc * R_c_b_;
  // d r / d d_phi = A * hat(p_b): row k is (A_k x p_b)^T.
  for (int k = 0; k < 2; ++k) {
    (*J)(k, 0) = A(k, 1) * p_b.z() - A(k, 2) * p_b.y();
    (*J)(k, 1) = A(k, 2) * p_b.x() - A(k, 0) * p_b.z();
    (*J)(k, 2) = A(k, 0) * p_b.y() - A(k, 1) * p_b.x();
  }
  J->rightCols<3>().noalias() = -J_pc * R_c_w_;
  return true;
}

bool usable(const PoseObservation& obs) {
  return obs.p_w.allFinite() && obs.uv.allFinite() && (obs.camera == 0 || obs.camera == 1) &&
         std::isfinite(obs.sigma_px) && obs.sigma_px > 0.0;
}

VisualTerms::VisualTerms(const StereoCalib& calib, double min_depth_m)
    : calib_(calib),
      max_radius2_{calib.cam0.intrinsics.max_valid_radius2(),
                   calib.cam1.intrinsics.max_valid_radius2()},
      min_depth_m_(min_depth_m) {}

double VisualTerms::linearise(const BodyState& x, const std::vector<PoseObservation>& observations,
                              const std::vector<bool>& active, double huber_chi2, Matrix6d* H,
                              Vector6d* b) const {
  const CameraView views[2] = {CameraView(calib_.cam0, max_radius2_[0], x.R_w_b, x.p_w_b),
                               CameraView(calib_.cam1, max_radius2_[1], x.R_w_b, x.p_w_b)};
  const double huber_delta = huber_chi2 > 0.0 ? std::sqrt(huber_chi2) : 0.0;
  H->setZero();
  b->setZero();
  double cost = 0.0;
  Eigen::Vector2d r;
  Matrix26d J;
  for (size_t k = 0; k < observations.size(); ++k) {
    if (!active[k]) continue;
    const PoseObservation& obs = observations[k];
    if (!views[obs.camera].residual(obs.p_w, obs.uv, min_depth_m_, &r, &J)) continue;
    const double info = 1.0 / (obs.sigma_px * obs.sigma_px);
    const double chi2 = r.squaredNorm() * info;
    double weight = info;
    if (huber_chi2 > 0.0 && chi2 > huber_chi2) {
      // Huber: rho = 2 delta e - delta^2 with e = sqrt(chi2); IRLS weight rho' = delta / e.
      const double e = std::sqrt(chi2);
      cost += 0.5 * (2.0 * huber_delta * e - huber_chi2);
      weight *= huber_delta / e;
    } else {
      cost += 0.5 * chi2;
    }
    const Eigen::Matrix<double, 6, 2> JtW = weight * J.transpose();
    H->noalias() += JtW * J;
    b->noalias() += JtW * r;
  }
  return cost;
}

void VisualTerms::chi2(const BodyState& x, const std::vector<PoseObservation>& observations,
                       std::vector<double>* chi2) const {
  const CameraView views[2] = {CameraView(calib_.cam0, max_radius2_[0], x.R_w_b, x.p_w_b),
                               CameraView(calib_.cam1, max_radius2_[1], x.R_w_b, x.p_w_b)};
  chi2->assign(observations.size(), std::numeric_limits<double>::infinity());
  Eigen::Vector2d r;
  for (size_t k = 0; k < observations.size(); ++k) {
    const PoseObservation& obs = observations[k];
    if (!usable(obs) || !views[obs.camera].residual(obs.p_w, obs.uv, min_depth_m_, &r)) continue;
    (*chi2)[k] = r.squaredNorm() / (obs.sigma_px * obs.sigma_px);
  }
}

}  // namespace hs
