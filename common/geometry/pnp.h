#pragma once
// Camera pose from 3D-2D correspondences with outliers: RANSAC over minimal EPnP solutions
// (OpenCV), on normalised image coordinates so any camera model can feed it.
#include <Eigen/Geometry>
#include <vector>

namespace hs {

struct PnpOptions {
  double threshold = 3.0 / 460.0;  // inlier reprojection error, normalised units (3 px at 460 px)
  int iterations = 200;
  double confidence = 0.99;
};

struct PnpResult {
  bool ok = false;
  Eigen::Isometry3d T_c_a = Eigen::Isometry3d::Identity();  // frame a -> camera
  std::vector<int> inliers;                                 // indices into the inputs
};

// p_a: points in any frame a; xy_c: where the camera sees them (x/z, y/z). Needs 4 or more.
PnpResult solve_pnp_ransac(const std::vector<Eigen::Vector3d>& p_a,
                           const std::vector<Eigen::Vector2d>& xy_c, const PnpOptions& options);

}  // namespace hs
