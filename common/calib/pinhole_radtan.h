#pragma once
// Pinhole camera with radial-tangential (plumb-bob, 4 coefficient) distortion, as in EuRoC.
//
// Pixel convention: pixel (u, v) = (column, row) has its centre at integer coordinates and
// covers [u - 0.5, u + 0.5] x [v - 0.5, v + 0.5]; the image spans [-0.5, width - 0.5] x
// [-0.5, height - 0.5]. This is the convention of EuRoC/Kalibr and OpenCV.
#include <Eigen/Core>

namespace hs {

struct PinholeRadtan {
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0;  // radial k1, k2; tangential p1, p2
  int width = 0, height = 0;              // pixels

  // Normalised undistorted (x/z, y/z) -> normalised distorted coordinates. Inline with its
  // Jacobian: every projection of the tracker and the bundle adjustments calls them.
  Eigen::Vector2d distort(const Eigen::Vector2d& xy) const;
  // d(distort)/d(xy).
  Eigen::Matrix2d distort_jacobian(const Eigen::Vector2d& xy) const;
  // Inverse of distort by Gauss-Newton; accurate to ~1e-12 inside the valid radius.
  Eigen::Vector2d undistort(const Eigen::Vector2d& xy_distorted) const;

  // Distorted pixel of a camera-frame point (no checks: z must be non-zero).
  Eigen::Vector2d project(const Eigen::Vector3d& p_c) const;
  // As project, and returns whether the point is usable: in front of the camera, within the
  // radius where the distortion is monotonic, and inside the image. `jacobian` (optional) is
  // d(pixel)/d(p_c), filled whenever z > 0.
  bool project(const Eigen::Vector3d& p_c, Eigen::Vector2d* uv,
               Eigen::Matrix<double, 2, 3>* jacobian = nullptr) const;

  // Normalised undistorted coordinates (x/z, y/z) of the ray through pixel `uv`.
  Eigen::Vector2d unproject_normalised(const Eigen::Vector2d& uv) const;
  // Unit bearing vector of the ray through pixel `uv`.
  Eigen::Vector3d unproject(const Eigen::Vector2d& uv) const;

  // Inside [-0.5 + border, size - 0.5 - border] in both axes.
  bool in_image(const Eigen::Vector2d& uv, double border = 0.0) const;
  // Squared normalised radius beyond which the radial distortion stops being monotonic
  // (infinity when it never does).
  double max_valid_radius2() const;
};

inline Eigen::Vector2d PinholeRadtan::distort(const Eigen::Vector2d& xy) const {
  const double x = xy.x(), y = xy.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k1 + k2 * r2);
  return {x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
          y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y};
}

inline Eigen::Matrix2d PinholeRadtan::distort_jacobian(const Eigen::Vector2d& xy) const {
  const double x = xy.x(), y = xy.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k1 + k2 * r2);
  const double dradial_dr2 = k1 + 2.0 * k2 * r2;  // d(radial)/dx = 2x * dradial_dr2
  Eigen::Matrix2d J;
  J(0, 0) = radial + 2.0 * x * x * dradial_dr2 + 2.0 * p1 * y + 6.0 * p2 * x;
  J(0, 1) = 2.0 * x * y * dradial_dr2 + 2.0 * p1 * x + 2.0 * p2 * y;
  J(1, 0) = 2.0 * x * y * dradial_dr2 + 2.0 * p1 * x + 2.0 * p2 * y;
  J(1, 1) = radial + 2.0 * y * y * dradial_dr2 + 6.0 * p1 * y + 2.0 * p2 * x;
  return J;
}

}  // namespace hs
