#include "mapper/schur_lm.h"

#include <ceres/sized_cost_function.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>

#include "common/calib/camera_calib.h"
#include "mapper/local_ba.h"
#include "tests/mapper/local_ba_test_scene.h"

namespace hs {
namespace {

// r = x - target, which cannot be evaluated beyond x = wall (as a point behind a camera).
class WalledCost : public ceres::SizedCostFunction<1, 1> {
 public:
  WalledCost(double target, double wall) : target_(target), wall_(wall) {}
  bool Evaluate(double const* const* x, double* r, double** J) const override {
    if (x[0][0] > wall_) return false;
    r[0] = x[0][0] - target_;
    if (J != nullptr && J[0] != nullptr) J[0][0] = 1.0;
    return true;
  }

 private:
  double target_, wall_;
};

// r = a + b (two blocks of 3).
class SumCost : public ceres::SizedCostFunction<3, 3, 3> {
 public:
  bool Evaluate(double const* const* x, double* r, double** J) const override {
    for (int i = 0; i < 3; ++i) r[i] = x[0][i] + x[1][i];
    for (int b = 0; b < 2; ++b) {
      if (J == nullptr || J[b] == nullptr) continue;
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(J[b]).setIdentity();
    }
    return true;
  }
};

ceres::Problem::Options borrowing() {
  ceres::Problem::Options o;
  o.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  return o;
}

TEST(SchurLm, FindsTheSameWindowAsCeres) {
  const StereoCalib calib = euroc_stereo_calib();
  std::mt19937 rng(11);
  test::BaScene scene = test::make_ba_scene(calib, {}, &rng);
  scene.input.keyframes.front().fixed = true;
  test::perturb(&scene.input, 0.05, 2.0 * EIGEN_PI / 180.0, 0.1, 0.05, &rng);
  LocalBaOptions options;
  options.time_budget_ms = 1e9;
  options.solver = LocalBaOptions::Solver::kCeres;
  const LocalBaResult ceres = LocalBundleAdjuster(calib, options).optimise(scene.input);
  options.solver = LocalBaOptions::Solver::kSchurLm;
  const LocalBaResult schur = LocalBundleAdjuster(calib, options).optimise(scene.input);

  EXPECT_NEAR(schur.stats.final_cost, ceres.stats.final_cost, 1e-3 * ceres.stats.final_cost);
  EXPECT_EQ(schur.outliers, ceres.outliers);
  for (size_t k = 0; k < ceres.keyframes.size(); ++k) {
    const NavState& a = ceres.keyframes[k].state;
    const NavState& b = schur.keyframes[k].state;
    EXPECT_LT((a.p_w_b - b.p_w_b).norm(), 1e-4) << "keyframe " << k;
    EXPECT_LT(a.q_w_b.angularDistance(b.q_w_b), 1e-5) << "keyframe " << k;
    EXPECT_LT((a.v_w - b.v_w).norm(), 1e-4) << "keyframe " << k;
  }
  std::vector<double> point_m;
  for (size_t k = 0; k < ceres.points.size(); ++k)
    point_m.push_back((ceres.points[k].p_w - schur.points[k].p_w).norm());
  // The few points the window barely constrains (one view left after the outliers) end where
  // each solver's damping left them along their unobserved direction.
  std::sort(point_m.begin(), point_m.end());
  EXPECT_LT(point_m[point_m.size() * 95 / 100], 1e-4);
}

// One unknown x (a keyframe-side block), wanted at 10 but unusable beyond 5.
class WalledProblem : public ::testing::Test {
 protected:
  void SetUp() override { problem_.AddResidualBlock(&cost_, nullptr, &x_); }
  SchurLmSummary solve(const SchurLmOptions& options) {
    return solve_schur_lm(
        problem_, [](const double*) { return false; }, options);
  }

  WalledCost cost_{10.0, 5.0};
  double x_ = 0.0;
  ceres::Problem problem_{borrowing()};
};

TEST_F(WalledProblem, AStepThatCannotBeEvaluatedIsRejectedAndShortened) {
  SchurLmOptions options;
  options.max_iterations = 20;
  const SchurLmSummary s = solve(options);
  ASSERT_TRUE(s.usable);
  EXPECT_GE(s.unsuccessful_steps, 1);  // the full step to 10 lies behind the wall
  EXPECT_GE(s.successful_steps, 1);
  EXPECT_LE(x_, 5.0);
  EXPECT_GT(x_, 4.0);  // it then creeps up to the wall
  EXPECT_DOUBLE_EQ(s.initial_cost, 50.0);
  EXPECT_NEAR(s.final_cost, 0.5 * (x_ - 10.0) * (x_ - 10.0), 1e-12);
}

TEST_F(WalledProblem, StopsBeforeAnIterationWhenToldAndOnAnUnusableStart) {
  x_ = 1.0;
  SchurLmOptions options;
  options.keep_going = [] { return false; };
  const SchurLmSummary held = solve(options);
  EXPECT_TRUE(held.usable);
  EXPECT_EQ(held.successful_steps + held.unsuccessful_steps, 0);
  EXPECT_EQ(x_, 1.0);

  x_ = 6.0;  // behind the wall from the start
  const SchurLmSummary unusable = solve({});
  EXPECT_FALSE(unusable.usable);
  EXPECT_EQ(x_, 6.0);
}

TEST(SchurLm, StructuresItCannotEliminateAreRefused) {
  SumCost cost;
  double a[3] = {1, 2, 3}, b[3] = {4, 5, 6};
  ceres::Problem problem(borrowing());
  problem.AddResidualBlock(&cost, nullptr, a, b);
  // A term between two free points.
  EXPECT_THROW(solve_schur_lm(problem, [](const double*) { return true; }, {}),
               std::invalid_argument);
  // With one of them held, the other is eliminated and solved exactly.
  problem.SetParameterBlockConstant(b);
  const SchurLmSummary s = solve_schur_lm(problem, [](const double*) { return true; }, {});
  EXPECT_TRUE(s.usable);
  EXPECT_NEAR(a[0], -4.0, 1e-6);
  EXPECT_NEAR(a[2], -6.0, 1e-6);
}

}  // namespace
}  // namespace hs
