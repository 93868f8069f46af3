// The trajectory's derivatives are exact: they match finite differences of the positions and
// rotations, and the spline is smooth across knots.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "common/sim/trajectory.h"
#include "scenario_test_util.h"

namespace hs::sim {
namespace {

TEST(QuinticSplineTest, SmoothAcrossKnotsAndDerivativesMatchFiniteDifferences) {
  std::vector<Eigen::Vector3d> control;
  for (int i = 0; i < 9; ++i)
    control.emplace_back(std::sin(i * 1.3), std::cos(i * 0.7) * i, 0.1 * i * i);
  for (const bool closed : {false, true}) {
    const QuinticSpline<3> spline(control, 0.5, closed);
    const double h = 1e-4;
    for (double s = 0.7; s < spline.length() - 0.1; s += 0.37) {
      const SplinePoint<3> p = spline.at(s), lo = spline.at(s - h), hi = spline.at(s + h);
      EXPECT_LT((p.d1 - (hi.value - lo.value) / (2 * h)).norm(), 1e-6) << s;
      EXPECT_LT((p.d2 - (hi.d1 - lo.d1) / (2 * h)).norm(), 1e-5) << s;
      EXPECT_LT((p.d3 - (hi.d2 - lo.d2) / (2 * h)).norm(), 1e-4) << s;
    }
    for (int knot = 1; knot < 6; ++knot) {  // continuity up to the third derivative
      const SplinePoint<3> a = spline.at(knot * 0.5 - 1e-9), b = spline.at(knot * 0.5 + 1e-9);
      EXPECT_LT((a.value - b.value).norm(), 1e-7);
      EXPECT_LT((a.d3 - b.d3).norm(), 1e-4);
    }
  }
}

TEST(QuinticSplineTest, OpenSplineRestsAtItsEnds) {
  const std::vector<Eigen::Vector2d> control{{0, 0}, {1, 2}, {3, 1}};
  const QuinticSpline<2> spline(control, 1.0, false);
  EXPECT_LT((spline.at(0.0).value - control.front()).norm(), 1e-12);
  EXPECT_LT(spline.at(0.0).d1.norm(), 1e-12);
  EXPECT_LT((spline.at(spline.length()).value - control.back()).norm(), 1e-12);
  EXPECT_LT(spline.at(spline.length() + 5.0).d2.norm(), 1e-12);
}

TEST(QuinticSplineTest, ClosedSplineIsPeriodic) {
  std::vector<Eigen::Vector2d> control;
  for (int i = 0; i < 8; ++i) control.emplace_back(std::cos(i * M_PI / 4), std::sin(i * M_PI / 4));
  const QuinticSpline<2> spline(control, 0.25, true);
  EXPECT_DOUBLE_EQ(spline.length(), 2.0);
  for (const double s : {0.1, 0.9, 1.7})
    EXPECT_LT((spline.at(s).value - spline.at(s + spline.length()).value).norm(), 1e-12);
}

// Body rate from a rotation finite difference: log(R(t-h)^T R(t+h)) / 2h.
Eigen::Vector3d numeric_omega_b(const Trajectory& tr, double t, double h) {
  const Eigen::AngleAxisd aa(tr.at(t - h).q_w_b.conjugate() * tr.at(t + h).q_w_b);
  return aa.axis() * aa.angle() / (2 * h);
}

void expect_exact_derivatives(const std::string& name) {
  const Scenario sc = testing::test_scenario(name);
  const Trajectory tr(sc.trajectory);
  const double h = 1e-4;
  double max_v = 0, max_a = 0, max_w = 0;
  for (double t = 0.013; t < sc.duration_s; t += 0.21) {
    const BodyKinematics k = tr.at(t), lo = tr.at(t - h), hi = tr.at(t + h);
    max_v = std::max(max_v, (k.v_w - (hi.p_w_b - lo.p_w_b) / (2 * h)).norm());
    max_a = std::max(max_a, (k.a_w - (hi.v_w - lo.v_w) / (2 * h)).norm());
    max_w = std::max(max_w, (k.omega_b - numeric_omega_b(tr, t, h)).norm());
  }
  EXPECT_LT(max_v, 1e-6) << name;
  EXPECT_LT(max_a, 1e-5) << name;
  EXPECT_LT(max_w, 1e-5) << name;
}

TEST(TrajectoryTest, DerivativesAreExactForTheMav) {
  expect_exact_derivatives("room_mav");
}
TEST(TrajectoryTest, DerivativesAreExactForTheVehicle) {
  expect_exact_derivatives("vehicle_loop");
}
TEST(TrajectoryTest, DerivativesAreExactDuringTheYawBurst) {
  expect_exact_derivatives("fast_rotation");
}

TEST(TrajectoryTest, ResamplesPolylineEvenly) {
  const std::vector<Eigen::Vector3d> square{{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}};
  const auto closed = resample_polyline(square, 1.0, true);
  ASSERT_EQ(closed.size(), 16u);
  for (size_t i = 0; i < closed.size(); ++i)
    EXPECT_NEAR((closed[(i + 1) % closed.size()] - closed[i]).norm(), 1.0, 1e-12);
  const auto open = resample_polyline(square, 1.0, false);
  ASSERT_EQ(open.size(), 13u);
  EXPECT_LT((open.back() - square.back()).norm(), 1e-12);
}

TEST(TrajectoryTest, MountLooksForwardWithBodyXUp) {
  TrajectoryOptions opt;
  opt.waypoints = {Eigen::Vector3d(0, 0, 1.5)};
  opt.yaw_mode = YawMode::kKeyframes;
  opt.yaw_deg = {90.0};
  const BodyKinematics k = Trajectory(opt).at(3.0);
  EXPECT_LT((k.q_w_b * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_LT((k.q_w_b * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
}

}  // namespace
}  // namespace hs::sim
