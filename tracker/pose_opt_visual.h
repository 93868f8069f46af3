#pragma once
// Reprojection terms of the motion-only optimisation (paper Eq. 5): r = pi(T_c_b T_b_w p_w) - uv
// for fixed map points, with analytic Jacobians w.r.t. the body pose in the tangent
// [d_phi, d_p] of pose_opt_types.h:
//   p_b = R_w_b^T (p_w - p_w_b), p_c = R_c_b p_b + t_c_b,
//   d p_c / d d_phi = R_c_b hat(p_b),   d p_c / d d_p = -R_c_b R_w_b^T.
#include <Eigen/Core>
#include <vector>

#include "common/calib/camera_calib.h"
#include "tracker/pose_opt_state.h"
#include "tracker/pose_opt_types.h"

namespace hs {

using Matrix26d = Eigen::Matrix<double, 2, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

// One camera of the rig as seen from a body pose, precomputed for many points.
class CameraView {
 public:
  // `max_radius2`: squared normalised radius of the camera's valid distortion range.
  CameraView(const CameraCalib& camera, double max_radius2, const Eigen::Matrix3d& R_w_b,
             const Eigen::Vector3d& p_w_b);
  // Residual (and d r / d [d_phi, d_p] when J is not null). False, with r and J unset, when the
  // point is nearer than min_depth_m or outside the valid distortion radius.
  bool residual(const Eigen::Vector3d& p_w, const Eigen::Vector2d& uv, double min_depth_m,
                Eigen::Vector2d* r, Matrix26d* J = nullptr) const;

 private:
  PinholeRadtan K_;
  double max_radius2_;
  Eigen::Matrix3d R_c_b_, R_b_w_, R_c_w_;
  Eigen::Vector3d p_w_b_, t_c_w_;
};

// Whether an observation can be used at all: finite values, a camera of the rig, sigma > 0.
bool usable(const PoseObservation& obs);

class VisualTerms {
 public:
  VisualTerms(const StereoCalib& calib, double min_depth_m);

  // Gauss-Newton system (H, b = gradient) and cost 0.5 * sum rho(chi2) of the active
  // observations, chi2 = |r|^2 / sigma^2, rho the Huber loss with threshold huber_chi2 (on
  // chi2; <= 0 for plain least squares). Observations that cannot be projected add nothing.
  double linearise(const BodyState& x, const std::vector<PoseObservation>& observations,
                   const std::vector<bool>& active, double huber_chi2, Matrix6d* H,
                   Vector6d* b) const;
  // chi2 of every observation at x; infinity for the unusable and unprojectable ones.
  void chi2(const BodyState& x, const std::vector<PoseObservation>& observations,
            std::vector<double>* chi2) const;

  const CameraCalib& camera(int index) const { return index == 0 ? calib_.cam0 : calib_.cam1; }
  double max_radius2(int index) const { return max_radius2_[index]; }

 private:
  StereoCalib calib_;
  double max_radius2_[2];
  double min_depth_m_;
};

}  // namespace hs
