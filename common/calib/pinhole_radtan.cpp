#include "common/calib/pinhole_radtan.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

namespace hs {

Eigen::Vector2d PinholeRadtan::undistort(const Eigen::Vector2d& xy_distorted) const {
  // Gauss-Newton (Newton, as the system is square) from the distorted point; the distortion is
  // close to identity near the centre and monotonic inside the valid radius, so this converges
  // in a handful of iterations.
  Eigen::Vector2d xy = xy_distorted;
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector2d residual = distort(xy) - xy_distorted;
    const Eigen::Matrix2d J = distort_jacobian(xy);
    const double det = J(0, 0) * J(1, 1) - J(0, 1) * J(1, 0);
    const Eigen::Vector2d step((J(1, 1) * residual.x() - J(0, 1) * residual.y()) / det,
                               (-J(1, 0) * residual.x() + J(0, 0) * residual.y()) / det);
    xy -= step;
    if (step.squaredNorm() < 1e-26) break;
  }
  return xy;
}

Eigen::Vector2d PinholeRadtan::project(const Eigen::Vector3d& p_c) const {
  const Eigen::Vector2d d = distort(p_c.head<2>() / p_c.z());
  return {fx * d.x() + cx, fy * d.y() + cy};
}

bool PinholeRadtan::project(const Eigen::Vector3d& p_c, Eigen::Vector2d* uv,
                            Eigen::Matrix<double, 2, 3>* jacobian) const {
  if (!(p_c.z() > 0.0)) return false;
  const double inv_z = 1.0 / p_c.z();
  const Eigen::Vector2d xy = p_c.head<2>() * inv_z;
  const Eigen::Vector2d d = distort(xy);
  *uv = {fx * d.x() + cx, fy * d.y() + cy};
  if (jacobian) {
    Eigen::Matrix<double, 2, 3> dxy_dp;
    dxy_dp << inv_z, 0.0, -xy.x() * inv_z, 0.0, inv_z, -xy.y() * inv_z;
    *jacobian = Eigen::Vector2d(fx, fy).asDiagonal() * distort_jacobian(xy) * dxy_dp;
  }
  return xy.squaredNorm() < max_valid_radius2() && in_image(*uv);
}

Eigen::Vector2d PinholeRadtan::unproject_normalised(const Eigen::Vector2d& uv) const {
  return undistort({(uv.x() - cx) / fx, (uv.y() - cy) / fy});
}

Eigen::Vector3d PinholeRadtan::unproject(const Eigen::Vector2d& uv) const {
  return unproject_normalised(uv).homogeneous().normalized();
}

bool PinholeRadtan::in_image(const Eigen::Vector2d& uv, double border) const {
  return uv.x() >= -0.5 + border && uv.y() >= -0.5 + border && uv.x() <= width - 0.5 - border &&
         uv.y() <= height - 0.5 - border;
}

double PinholeRadtan::max_valid_radius2() const {
  // d(r * radial(r^2))/dr = 1 + 3 k1 s + 5 k2 s^2 with s = r^2: first positive root.
  const double inf = std::numeric_limits<double>::infinity();
  if (k2 == 0.0) return k1 < 0.0 ? -1.0 / (3.0 * k1) : inf;
  const double disc = 9.0 * k1 * k1 - 20.0 * k2;
  if (disc < 0.0) return inf;
  const double sq = std::sqrt(disc);
  double best = inf;
  for (const double s : {(-3.0 * k1 - sq) / (10.0 * k2), (-3.0 * k1 + sq) / (10.0 * k2)}) {
    if (s > 0.0 && s < best) best = s;
  }
  return best;
}

}  // namespace hs
