#include "common/geometry/pnp.h"

#include <gtest/gtest.h>

#include <random>

namespace hs {
namespace {

TEST(Pnp, RecoversThePoseDespiteAThirdOfOutliers) {
  Eigen::Isometry3d T_c_a = Eigen::Isometry3d::Identity();
  T_c_a.rotate(Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.3, 1.0, -0.2).normalized()));
  T_c_a.translation() = Eigen::Vector3d(0.5, -0.2, 1.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  std::vector<Eigen::Vector3d> p_a;
  std::vector<Eigen::Vector2d> xy;
  std::vector<bool> outlier;
  while (p_a.size() < 90) {
    const Eigen::Vector3d p(u(rng), u(rng), 3.0 + u(rng));
    const Eigen::Vector3d p_c = T_c_a * p;
    if (p_c.z() < 0.5) continue;
    p_a.push_back(p);
    outlier.push_back(p_a.size() % 3 == 0);
    const Eigen::Vector2d noise(u(rng), u(rng));
    xy.push_back(p_c.head<2>() / p_c.z() +
                 (outlier.back() ? Eigen::Vector2d(0.1 * noise) : Eigen::Vector2d::Zero()));
  }
  const PnpResult r = solve_pnp_ransac(p_a, xy, {});
  ASSERT_TRUE(r.ok);
  EXPECT_LT((r.T_c_a.translation() - T_c_a.translation()).norm(), 1e-4);
  EXPECT_LT(Eigen::AngleAxisd(r.T_c_a.linear().transpose() * T_c_a.linear()).angle(), 1e-4);
  EXPECT_EQ(r.inliers.size(), 60u);
  for (int i : r.inliers) EXPECT_FALSE(outlier[static_cast<size_t>(i)]) << i;
}

TEST(Pnp, TooFewPointsIsNoPoseAndMismatchedInputIsAnError) {
  EXPECT_FALSE(
      solve_pnp_ransac({{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}, {{0, 0}, {1, 0}, {0, 1}}, {}).ok);
  EXPECT_THROW(solve_pnp_ransac({{0, 0, 1}}, {}, {}), std::invalid_argument);
}

}  // namespace
}  // namespace hs
