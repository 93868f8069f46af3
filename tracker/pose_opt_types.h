#pragma once
// Options, inputs and result of the tracker's motion-only optimisation (paper Eq. 5-6 and the
// failure check of Algorithm 1).
//
// Tangent-space convention of every Jacobian, information and covariance matrix here:
//   R_w_b <- R_w_b * Exp(d_phi)   (right perturbation: d_phi in the body frame)
//   p_w_b <- p_w_b + d_p          (world frame), v_w <- v_w + d_v, biases additively,
// ordered [d_phi, d_p, d_v, d_bg, d_ba] (15) or [d_phi, d_p] (6, the pose). This matches
// common/imu/imu_residual.h and the (rotation, position) order of odometry_t.covariance.
#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

#include "common/core/types.h"

namespace hs {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Matrix15d = Eigen::Matrix<double, 15, 15>;

struct PoseOptOptions {
  // Robust estimation as in ORB-SLAM's motion-only BA: `rounds` rounds of at most
  // `iterations_per_round` Levenberg-Marquardt iterations. After each round every observation
  // is re-classified with the chi2 test at the current estimate; outliers are left out of the
  // next round (and may come back). The first `huber_rounds` rounds use the Huber loss.
  int rounds = 4;
  int iterations_per_round = 10;
  int huber_rounds = 3;
  double chi2_threshold = 5.991;  // 95% of chi2 with 2 DoF; also the Huber threshold (squared)
  double min_depth_m = 0.05;      // closer to (or behind) the camera: outlier
  // A round stops once a step is shorter than this many standard deviations of the estimate
  // (sqrt(step^T H step), H the Gauss-Newton Hessian): far below the noise, in any unit.
  double min_step_sigma = 0.01;
  double initial_lambda = 1e-6;  // LM damping, relative to the Hessian diagonal
  double max_lambda = 1e6;       // a round gives up once the damping would exceed this

  // Failure check (paper Algorithm 1: VM < N_min or EPE > threshold).
  int min_inliers = 15;            // N_min
  double max_rms_px = 2.0;         // RMS reprojection error of the inliers, pixels
  double max_translation_m = 1.0;  // from the initial guess: beyond this it diverged
  double max_rotation_rad = 0.5;
};

// A fixed map point seen in one camera of the rig.
struct PoseObservation {
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  // distorted pixel
  int camera = 0;                                // 0: cam0 (left), 1: cam1 (right)
  double sigma_px = 1.0;                         // standard deviation of uv, per axis
};

// Pixel sigma of a keypoint detected at pyramid `level` (level 0 has sigma0_px).
inline double level_sigma_px(int level, double scale_factor = 1.2, double sigma0_px = 1.0) {
  return sigma0_px * std::pow(scale_factor, level);
}

// The state the IMU term links the current frame to.
struct PreviousState {
  NavState state;
  // Fixed: a keyframe the mapper has optimised. Free: a recent frame, estimated jointly under a
  // Gaussian prior centred on `state` with this information (from its own optimisation: the
  // `information` of that frame's PoseOptResult).
  bool fixed = true;
  Matrix15d information = Matrix15d::Zero();
};

enum class PoseOptStatus { kOk, kNonFinite, kTooFewInliers, kDiverged, kRmsTooHigh };
const char* to_string(PoseOptStatus status);

struct PoseOptResult {
  PoseOptStatus status = PoseOptStatus::kNonFinite;
  std::string reason;  // human-readable detail; empty when ok
  bool valid() const { return status == PoseOptStatus::kOk; }

  NavState state;  // filled even when invalid (the estimate the check rejected)
  // Covariance of the pose, tangent [d_phi, d_p]; all zero when it cannot be computed.
  Matrix6d pose_covariance = Matrix6d::Zero();
  // Visual-inertial mode: marginal information of `state` (15 dims) for the next frame's prior.
  // Zero in pose-only mode.
  Matrix15d information = Matrix15d::Zero();

  std::vector<bool> inliers;  // per observation, from the last chi2 classification
  int num_inliers = 0;
  double rms_px = 0.0;        // RMS of the inliers' reprojection error norms, pixels
  double chi2_inliers = 0.0;  // sum of the inliers' whitened squared errors
  double chi2_max = 0.0;      // largest inlier chi2
  double chi2_imu = 0.0;      // visual-inertial mode: IMU + bias random walk (+ prior) terms
  int iterations = 0;         // LM iterations over all rounds
};

}  // namespace hs
