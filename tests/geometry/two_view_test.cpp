#include "common/geometry/two_view.h"

#include <gtest/gtest.h>

#include <random>

namespace hs {
namespace {

constexpr double kFx = 460.0;  // EuRoC's focal length: 1 px is 1/460 in normalised units

struct Pair {
  std::vector<Eigen::Vector2d> xy_a, xy_b;
  std::vector<Eigen::Vector3d> p_a;  // truth, frame a
  std::vector<bool> outlier;
};

// Points p_a seen from frame a and from b = T_a_b^-1, with 0.5 px noise and a share of matches
// replaced by random ones.
Pair observe(const std::vector<Eigen::Vector3d>& points, const Eigen::Isometry3d& T_a_b,
             double outlier_share, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, 0.5 / kFx);
  std::uniform_real_distribution<double> anywhere(-0.6, 0.6), u(0.0, 1.0);
  Pair out;
  const Eigen::Isometry3d T_b_a = T_a_b.inverse();
  for (const Eigen::Vector3d& p_a : points) {
    const Eigen::Vector3d p_b = T_b_a * p_a;
    if (p_a.z() < 0.3 || p_b.z() < 0.3) continue;
    const bool outlier = u(rng) < outlier_share;
    out.p_a.push_back(p_a);
    out.outlier.push_back(outlier);
    out.xy_a.push_back(p_a.hnormalized() + Eigen::Vector2d(noise(rng), noise(rng)));
    out.xy_b.push_back(
        outlier ? Eigen::Vector2d(anywhere(rng), anywhere(rng))
                : Eigen::Vector2d(p_b.hnormalized() + Eigen::Vector2d(noise(rng), noise(rng))));
  }
  return out;
}

Eigen::Isometry3d motion(const Eigen::Vector3d& t, double yaw_deg) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() =
      Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d(0.1, 1.0, 0.05).normalized())
          .toRotationMatrix();
  T.translation() = t;
  return T;
}

double angle_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180.0 / M_PI;
}

double direction_error_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

std::vector<Eigen::Vector3d> room(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-2.0, 2.0), depth(2.0, 6.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < n; ++i) points.emplace_back(u(rng), u(rng), depth(rng));
  return points;
}

// A room-like scene, 20 cm sideways and forward with 4 deg of rotation, a fifth of the matches
// wrong: the essential matrix is chosen, the motion and the structure (up to scale) recovered.
TEST(TwoView, AGeneralSceneGivesTheMotionAndTheStructureUpToScale) {
  std::mt19937 rng(3);
  const Eigen::Isometry3d T_a_b = motion({0.15, 0.02, 0.12}, 4.0);
  const Pair pair = observe(room(300, rng), T_a_b, 0.2, rng);
  TwoViewOptions options;
  options.sigma = 1.0 / kFx;
  const TwoViewResult r = reconstruct_two_view(pair.xy_a, pair.xy_b, options);
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_FALSE(r.homography) << r.homography_score_share;
  EXPECT_LT(angle_deg(r.T_a_b.linear(), T_a_b.linear()), 0.1);
  EXPECT_LT(direction_error_deg(r.T_a_b.translation(), T_a_b.translation()), 1.5);
  EXPECT_NEAR(r.T_a_b.translation().norm(), 1.0, 1e-9);
  int wrong = 0;
  for (int i : r.inliers) wrong += pair.outlier[static_cast<size_t>(i)];
  EXPECT_LT(wrong, 5);
  ASSERT_GT(r.triangulated.size(), 150u);
  // The structure is the truth scaled by 1 / |t|.
  const double scale = T_a_b.translation().norm();
  std::vector<double> errors;
  for (size_t k = 0; k < r.triangulated.size(); ++k) {
    const size_t i = static_cast<size_t>(r.triangulated[k]);
    if (pair.outlier[i]) continue;
    errors.push_back((scale * r.p_a[k] - pair.p_a[i]).norm() / pair.p_a[i].norm());
  }
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  EXPECT_LT(errors[errors.size() / 2], 0.03);  // median relative error
  EXPECT_GT(r.median_parallax_rad, options.min_parallax_rad);
}

// All points on a wall: the homography explains the matches better and its decomposition gives
// the motion.
TEST(TwoView, APlanarSceneTakesTheHomography) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-3.0, 3.0);  // EuRoC's field of view at 4 m
  std::vector<Eigen::Vector3d> wall;
  for (int i = 0; i < 300; ++i) {
    const double x = u(rng), y = u(rng);
    wall.emplace_back(x, y, 4.0 + 0.3 * x);  // slanted: not fronto-parallel
  }
  const Eigen::Isometry3d T_a_b = motion({0.3, 0.05, 0.1}, 3.0);
  const Pair pair = observe(wall, T_a_b, 0.1, rng);
  const TwoViewResult r = reconstruct_two_view(pair.xy_a, pair.xy_b);
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_TRUE(r.homography) << r.homography_score_share << " " << r.inliers.size();
  EXPECT_LT(angle_deg(r.T_a_b.linear(), T_a_b.linear()), 0.3);
  EXPECT_LT(direction_error_deg(r.T_a_b.translation(), T_a_b.translation()), 3.0);
}

// The camera turned but hardly moved: no baseline to triangulate from, whichever model fits.
TEST(TwoView, ARotationWithoutTranslationIsRefusedForLackOfParallax) {
  std::mt19937 rng(9);
  const Pair pair = observe(room(300, rng), motion({0.002, 0.0, 0.0}, 5.0), 0.1, rng);
  const TwoViewResult r = reconstruct_two_view(pair.xy_a, pair.xy_b);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.reason.empty());
  EXPECT_TRUE(r.reason.find("parallax") != std::string::npos ||
              r.reason.find("ambiguous") != std::string::npos ||
              r.reason.find("front") != std::string::npos)
      << r.reason;
}

TEST(TwoView, TooFewOrMismatchedMatchesAreRefused) {
  std::mt19937 rng(11);
  const Pair pair = observe(room(30, rng), motion({0.2, 0.0, 0.0}, 2.0), 0.0, rng);
  const TwoViewResult r = reconstruct_two_view(pair.xy_a, pair.xy_b);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("too few matches"), std::string::npos) << r.reason;
  EXPECT_THROW(reconstruct_two_view(pair.xy_a, {}), std::invalid_argument);
}

// The four motions of an essential matrix include the true one, and it is the only one with
// the points in front of both cameras.
TEST(TwoView, OfTheEssentialMatrixsFourMotionsOnlyTheTrueOneIsInFront) {
  const Eigen::Isometry3d T_a_b = motion({0.2, -0.1, 0.05}, 10.0);
  const Eigen::Vector3d t = T_a_b.translation().normalized();
  Eigen::Matrix3d t_x;
  t_x << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
  const std::vector<Eigen::Isometry3d> motions = decompose_essential(t_x * T_a_b.linear());
  ASSERT_EQ(motions.size(), 4u);
  int matching = 0;
  for (const Eigen::Isometry3d& T : motions) {
    EXPECT_NEAR(T.linear().determinant(), 1.0, 1e-9);
    matching += angle_deg(T.linear(), T_a_b.linear()) < 1e-6 &&
                direction_error_deg(T.translation(), t) < 1e-6;
  }
  EXPECT_EQ(matching, 1);
}

}  // namespace
}  // namespace hs
