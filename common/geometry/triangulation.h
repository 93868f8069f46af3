#pragma once
// Two-view triangulation from normalised image coordinates (x/z, y/z).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <vector>

namespace hs {

// Point in frame a seen at normalised coordinates xy_a in frame a and xy_b in frame b, where
// T_a_b maps frame-b points into frame a. Linear (DLT) solution; nullopt when the rays are
// (nearly) parallel or the point is behind either camera.
std::optional<Eigen::Vector3d> triangulate_two_view(const Eigen::Vector2d& xy_a,
                                                    const Eigen::Vector2d& xy_b,
                                                    const Eigen::Isometry3d& T_a_b);

// A point seen from several cameras: its normalised coordinates in a camera at T_c_w.
struct PointView {
  Eigen::Isometry3d T_c_w;
  Eigen::Vector2d xy;
};

struct RefinedPoint {
  Eigen::Vector3d p_w;
  double rms = 0.0;  // of the normalised-coordinate residuals
};

// Gauss-Newton on the reprojection error of `p_w` in all the views; nullopt when the point ends
// behind a camera or the problem is singular.
std::optional<RefinedPoint> refine_point(const Eigen::Vector3d& p_w,
                                         const std::vector<PointView>& views, int iterations = 3);

// Parallax angle (radians) at p_a between the rays to the two camera centres.
double parallax_angle(const Eigen::Vector3d& p_a, const Eigen::Isometry3d& T_a_b);

}  // namespace hs
