#include "common/geometry/triangulation.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace hs {

std::optional<Eigen::Vector3d> triangulate_two_view(const Eigen::Vector2d& xy_a,
                                                    const Eigen::Vector2d& xy_b,
                                                    const Eigen::Isometry3d& T_a_b) {
  const Eigen::Vector3d ray_a = xy_a.homogeneous().normalized();
  const Eigen::Vector3d ray_b_in_a = T_a_b.linear() * xy_b.homogeneous().normalized();
  if (ray_a.dot(ray_b_in_a) > 1.0 - 1e-12) return std::nullopt;  // parallel: depth unobservable
  // Projection matrices in frame a: P_a = [I | 0], P_b = T_b_a (3x4).
  const Eigen::Isometry3d T_b_a = T_a_b.inverse();
  Eigen::Matrix<double, 3, 4> P_a = Eigen::Matrix<double, 3, 4>::Zero();
  P_a.leftCols<3>().setIdentity();
  const Eigen::Matrix<double, 3, 4> P_b = T_b_a.matrix().topRows<3>();

  Eigen::Matrix4d A;
  A.row(0) = xy_a.x() * P_a.row(2) - P_a.row(0);
  A.row(1) = xy_a.y() * P_a.row(2) - P_a.row(1);
  A.row(2) = xy_b.x() * P_b.row(2) - P_b.row(0);
  A.row(3) = xy_b.y() * P_b.row(2) - P_b.row(1);
  const Eigen::JacobiSVD<Eigen::Matrix4d> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector4d X = svd.matrixV().col(3);
  if (std::abs(X.w()) < 1e-12) return std::nullopt;  // point at infinity
  const Eigen::Vector3d p_a = X.head<3>() / X.w();
  if (p_a.z() <= 0.0 || (T_b_a * p_a).z() <= 0.0) return std::nullopt;
  return p_a;
}

double parallax_angle(const Eigen::Vector3d& p_a, const Eigen::Isometry3d& T_a_b) {
  const Eigen::Vector3d ray_a = p_a.normalized();
  const Eigen::Vector3d ray_b = (p_a - T_a_b.translation()).normalized();
  return std::acos(std::clamp(ray_a.dot(ray_b), -1.0, 1.0));
}

}  // namespace hs
