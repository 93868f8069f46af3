#pragma once
// Reprojection residual of a map point in one camera of the rig, whitened by the pixel sigma:
//   r = (pi(R_c_b p_b + t_c_b) - uv) / sigma,  p_b = R_w_b^T (p_w - p_w_b),
// with analytic Jacobians (pose block in the tangent layout of mapper/pose_manifold.h):
//   d p_c / d d_phi = R_c_b hat(p_b),  d p_c / d d_p = -R_c_w,  d p_c / d p_w = R_c_w.
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "common/calib/camera_calib.h"
#include "mapper/pose_manifold.h"

namespace hs {

// One camera of the rig, prepared for projection.
struct RigCamera {
  explicit RigCamera(const CameraCalib& calib);
  PinholeRadtan K;
  double max_radius2;  // valid distortion range, squared normalised radius
  Eigen::Matrix3d R_c_b;
  Eigen::Vector3d t_c_b;
};

class ReprojectionCost : public ceres::SizedCostFunction<2, kPoseSize, 3> {
 public:
  // Evaluate() fails (Ceres then rejects the step) when the point is nearer than min_depth_m
  // or outside the camera's valid distortion radius. `camera` must outlive the cost: a window
  // holds thousands of costs, and Ceres' evaluation misses the cache on each one, so they share
  // the camera rather than each carry a copy (80 bytes instead of 270).
  ReprojectionCost(const RigCamera& camera, const Eigen::Vector2d& uv, double sigma_px,
                   double min_depth_m);
  ReprojectionCost(RigCamera&&, const Eigen::Vector2d&, double, double) = delete;
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  const RigCamera* camera_;
  Eigen::Vector2d uv_;
  double inv_sigma_;
  double min_depth_m_;
};

}  // namespace hs
