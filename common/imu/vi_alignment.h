#pragma once
// Visual-inertial alignment for a start in motion: gyro bias, per-pose velocities, gravity (and,
// when the window observes it, the accelerometer bias) from a short window of metric body poses
// (stereo vision) and the IMU preintegrations between consecutive poses; or, from mono poses known
// up to scale, the scale too.
//
// Method, as a maximum a posteriori estimate with each vision pose an independent prior:
// (1) attitudes and gyro bias by Gauss-Newton on the vision attitudes and the rotation residuals
// Log(dR_ij(bg)^T R_i^T R_j), re-integrating at each step; (2) positions, velocities and an
// unconstrained gravity vector by weighted linear least squares on the vision positions and
// the velocity and position equations of each pair; (3) gravity refined on the sphere |g| = G
// with a 2-DoF tangent update, with the accel bias added when its marginal uncertainty is small
// enough; (4) optionally, for vision attitudes that drift (a mono odometry's), the gyro bias
// again from the translational equations, since (1) takes such a drift for bias. The IMU
// equations are weighted by the preintegration covariances. For a mono camera
// the vision positions carry an unknown scale, one more unknown of step (2) (as in Mur-Artal
// and Tardos' visual-inertial monocular initialisation).
//
// Limits: the window must be short enough for a constant bias and the vision poses must be
// metric and drift-free over it. Without rotation the accel bias cannot be told from a gravity
// tilt (only g + R ba is seen); then the bias stays at the preintegrations' linearisation value
// and `weak_excitation` is set, so a bias b tilts gravity by about |b| / G. Vision noise is
// treated as independent per pose, which real odometry is not, so the reported sigmas are
// optimistic for real data; use them to compare windows rather than as calibrated values.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "common/imu/imu_residual.h"
#include "common/imu/preintegration.h"

namespace hs {

struct TimedPose {
  int64_t t_ns = 0;
  Eigen::Isometry3d T_w_b = Eigen::Isometry3d::Identity();  // body -> vision world, metric
};

struct ViAlignmentOptions {
  double gravity_magnitude = kGravityMagnitude;  // G, m/s^2
  // Vision pose noise, independent between poses: the weight of each pose as a prior. Metric
  // also up to scale (the prior's residual is the metric position's).
  double vision_position_sigma_m = 0.005;
  double vision_rotation_sigma_rad = 0.002;
  // > 0: the vision attitudes may drift by up to about this rate (rad/s; a mono odometry's do),
  // which step (1) would take for gyro bias. The bias is then refined from the translational
  // equations too (the drift tilts gravity against the accelerometer), under this prior.
  double vision_rotation_drift_sigma = 0.0;
  int gyro_bias_iterations = 10;  // Gauss-Newton steps, on first-order deltas included
  int gravity_iterations = 5;
  // The accel bias is estimated only when this is set and the largest marginal standard
  // deviation of its estimate (m/s^2) is at most max_accel_bias_sigma.
  bool estimate_accel_bias = true;
  double max_accel_bias_sigma = 0.02;
  // > 0: the accel bias is always estimated, with a prior of this standard deviation (m/s^2)
  // about the preintegrations' linearisation value; weak_excitation still reports a window
  // that alone would not separate it from a gravity tilt.
  double accel_bias_prior_sigma = 0.0;
  // Sanity checks that refuse the window.
  double max_gyro_bias_norm = 0.3;      // rad/s
  double max_gravity_norm_error = 1.0;  // | |g| - G | of the unconstrained solution, m/s^2
  // Up to scale (mono): refused as "not enough acceleration" when the scale's standard
  // deviation in the unconstrained solution is above this share of it.
  double max_scale_sigma = 0.05;
};

struct ViAlignmentResult {
  bool ok = false;     // estimates below are usable
  std::string reason;  // why not; empty when ok

  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();   // rad/s
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();  // m/s^2
  bool accel_bias_estimated = false;
  // The window cannot separate accel bias from gravity tilt (too little rotation); gravity was
  // estimated with the accel bias held at the preintegrations' linearisation value.
  bool weak_excitation = false;
  // Up to scale: metric = scale * vision (1 for metric poses), and its standard deviation.
  double scale = 1.0;
  double scale_sigma = 0.0;

  std::vector<Eigen::Vector3d> v_w;                      // body velocity at each pose, vision world
  Eigen::Vector3d g_w = Eigen::Vector3d::Zero();         // gravity in the vision world, |g_w| = G
  Eigen::Matrix3d R_wg_w = Eigen::Matrix3d::Identity();  // vision world -> gravity-aligned
  double gravity_norm_unconstrained = 0.0;               // |g| of step (2), a consistency check

  // Fit quality. Corrections: RMS over poses of refined minus vision attitude / position,
  // comparable to the vision sigmas. Chi-square per degree of freedom of the attitude and of
  // the translational problem: near 1 when the noise model in the options is right.
  double rotation_correction_rms_rad = 0.0;
  double position_correction_rms_m = 0.0;
  double rotation_chi2_per_dof = 0.0;
  double translation_chi2_per_dof = 0.0;
  // Conditioning: largest marginal standard deviations from the weighted normal equations, and
  // the ratio of smallest to largest eigenvalue of the joint information of [gravity tilt * G,
  // accel bias] (both m/s^2), near 0 when they are not separable. The last two are computed
  // only with options.estimate_accel_bias.
  double gyro_bias_sigma = 0.0;   // rad/s
  double tilt_sigma_rad = 0.0;    // gravity direction
  double accel_bias_sigma = 0.0;  // m/s^2, infinite when unobservable
  double gravity_accel_bias_conditioning = 0.0;
};

// `poses` are N >= 3 poses in increasing time; `pims[k]` preintegrates the IMU over
// [poses[k].t_ns, poses[k + 1].t_ns] (N - 1 of them, linearised at any bias; the accel part of
// pims[0]'s bias is the value held when the accel bias is not estimated). Refuses (ok = false)
// inconsistent, non-finite or gapped input and windows failing the option checks.
ViAlignmentResult align_visual_inertial(const std::vector<TimedPose>& poses,
                                        const std::vector<ImuPreintegration>& pims,
                                        const ViAlignmentOptions& options = {});

// The same from a mono camera's poses, known up to scale: `camera_poses` are T_w_c (in the
// TimedPose's T_w_b field) with positions s times too small, T_b_c the metric extrinsic. The
// scale is estimated with the rest (velocities and positions in the result are metric); a
// window without enough acceleration to observe it is refused.
ViAlignmentResult align_visual_inertial_up_to_scale(const std::vector<TimedPose>& camera_poses,
                                                    const Eigen::Isometry3d& T_b_c,
                                                    const std::vector<ImuPreintegration>& pims,
                                                    const ViAlignmentOptions& options = {});

}  // namespace hs
