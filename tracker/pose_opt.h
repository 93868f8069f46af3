#pragma once
// Motion-only optimisation of the current frame after direct alignment (paper Eq. 5-6, Sec.
// 3.4) with the failure check of Algorithm 1. Robust Levenberg-Marquardt on reprojection errors
// of fixed map points (see PoseOptOptions), in two modes:
//  (a) pose only (6 DoF): initialisation and relocalisation;
//  (b) visual-inertial: the full state x_j = (R, p, v, bg, ba) of the current frame with an IMU
//      preintegration term and bias random walk to the previous state x_i, which is either
//      fixed (a keyframe after the mapper's update) or estimated jointly under the Gaussian
//      prior of its own optimisation. x_i is then marginalised (Schur complement) and the
//      15x15 information of x_j returned as the next frame's prior. The IMU term uses x_i's
//      biases, so with a fixed x_i the biases of x_j stay at the keyframe's (the mapper estimates
//      them); a chain of free previous frames estimates them here.
// Conventions (tangent order, perturbations): pose_opt_types.h.
#include <Eigen/Core>
#include <vector>

#include "common/calib/camera_calib.h"
#include "common/imu/imu_residual.h"
#include "common/imu/preintegration.h"
#include "tracker/pose_opt_types.h"
#include "tracker/pose_opt_visual.h"

namespace hs {

class PoseOptimizer {
 public:
  // Throws std::invalid_argument for options out of range (no rounds or iterations,
  // non-positive chi2 threshold).
  explicit PoseOptimizer(const StereoCalib& calib, const PoseOptOptions& options = {},
                         const Eigen::Vector3d& g_w = default_gravity_w());

  // Mode (a). Starts at `initial`; its velocity, biases and time are copied to the result.
  PoseOptResult optimise_pose(const NavState& initial,
                              const std::vector<PoseObservation>& observations) const;

  // Mode (b). `pim` spans [previous.state.t_ns, current time] and is linearised near the
  // previous bias (call pim.update_bias() first when that bias moved); `initial` is the starting
  // estimate of the current state, typically predict(previous.state, pim). Throws
  // std::invalid_argument when pim does not span [previous.state.t_ns, initial.t_ns].
  PoseOptResult optimise_inertial(const NavState& initial,
                                  const std::vector<PoseObservation>& observations,
                                  const ImuPreintegration& pim,
                                  const PreviousState& previous) const;

  const PoseOptOptions& options() const { return options_; }
  void set_gravity(const Eigen::Vector3d& g_w) { g_w_ = g_w; }
  const Eigen::Vector3d& gravity() const { return g_w_; }

 private:
  PoseOptOptions options_;
  VisualTerms visual_;
  Eigen::Vector3d g_w_;
};

}  // namespace hs
