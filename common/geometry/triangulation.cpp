#include "common/geometry/triangulation.h"

#include <Eigen/Cholesky>
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

std::optional<RefinedPoint> refine_point(const Eigen::Vector3d& p_w,
                                         const std::vector<PointView>& views, int iterations) {
  RefinedPoint r{p_w, 0.0};
  for (int it = 0; it <= iterations; ++it) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    double sq = 0.0;
    for (const PointView& v : views) {
      const Eigen::Vector3d p_c = v.T_c_w * r.p_w;
      if (p_c.z() <= 1e-6) return std::nullopt;
      const Eigen::Vector2d e = p_c.head<2>() / p_c.z() - v.xy;
      sq += e.squaredNorm();
      Eigen::Matrix<double, 2, 3> J_c;
      J_c << 1.0 / p_c.z(), 0.0, -p_c.x() / (p_c.z() * p_c.z()), 0.0, 1.0 / p_c.z(),
          -p_c.y() / (p_c.z() * p_c.z());
      const Eigen::Matrix<double, 2, 3> J = J_c * v.T_c_w.linear();
      H += J.transpose() * J;
      g += J.transpose() * e;
    }
    r.rms = std::sqrt(sq / static_cast<double>(std::max<size_t>(1, views.size())));
    if (it == iterations) break;
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(H);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-12)) return std::nullopt;
    r.p_w -= ldlt.solve(g);
  }
  return r;
}

double parallax_angle(const Eigen::Vector3d& p_a, const Eigen::Isometry3d& T_a_b) {
  const Eigen::Vector3d ray_a = p_a.normalized();
  const Eigen::Vector3d ray_b = (p_a - T_a_b.translation()).normalized();
  return std::acos(std::clamp(ray_a.dot(ray_b), -1.0, 1.0));
}

}  // namespace hs
