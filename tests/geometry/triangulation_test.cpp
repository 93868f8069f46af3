#include "common/geometry/triangulation.h"

#include <gtest/gtest.h>

namespace hs {
namespace {

Eigen::Vector2d normalised(const Eigen::Vector3d& p) {
  return p.head<2>() / p.z();
}

TEST(Triangulation, RecoversPointFromStereoPair) {
  Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();
  T_a_b.translate(Eigen::Vector3d(0.11, 0.001, -0.002));
  T_a_b.rotate(Eigen::AngleAxisd(0.01, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()));
  for (const Eigen::Vector3d& p_a : {Eigen::Vector3d(0.3, -0.2, 1.5), Eigen::Vector3d(-2, 1, 12)}) {
    const Eigen::Vector3d p_b = T_a_b.inverse() * p_a;
    const auto est = triangulate_two_view(normalised(p_a), normalised(p_b), T_a_b);
    ASSERT_TRUE(est.has_value());
    EXPECT_LT((*est - p_a).norm(), 1e-9 * p_a.norm());
    EXPECT_GT(parallax_angle(p_a, T_a_b), 0.0);
  }
}

TEST(Triangulation, RejectsPointsBehindAndParallelRays) {
  Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();
  T_a_b.translate(Eigen::Vector3d(0.1, 0, 0));
  // Diverging rays meet behind the cameras.
  EXPECT_FALSE(triangulate_two_view({0.1, 0.0}, {0.2, 0.0}, T_a_b).has_value());
  // No baseline: parallel rays.
  EXPECT_FALSE(
      triangulate_two_view({0.1, 0.0}, {0.1, 0.0}, Eigen::Isometry3d::Identity()).has_value());
}

// Four cameras along a line looking at a point: refined from a start 10% off in depth, it lands
// on the point; a point that ends behind a camera is refused.
TEST(Triangulation, RefinePointFromSeveralViews) {
  const Eigen::Vector3d p_w(0.4, -0.3, 4.0);
  std::vector<PointView> views;
  for (double x : {0.0, 0.1, 0.25, 0.4}) {
    Eigen::Isometry3d T_c_w = Eigen::Isometry3d::Identity();
    T_c_w.translation() = Eigen::Vector3d(-x, 0.0, 0.0);
    views.push_back({T_c_w, normalised(T_c_w * p_w)});
  }
  const auto r = refine_point(1.1 * p_w, views, 5);
  ASSERT_TRUE(r.has_value());
  EXPECT_LT((r->p_w - p_w).norm(), 1e-6);
  EXPECT_LT(r->rms, 1e-9);
  EXPECT_FALSE(refine_point(Eigen::Vector3d(0.4, -0.3, -4.0), views).has_value());
}

}  // namespace
}  // namespace hs
