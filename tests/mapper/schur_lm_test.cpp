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
  void SetUp() override { lm_.add_term(&cost_, nullptr, {&x_}); }
  SchurLmSummary solve(const SchurLmOptions& options) { return lm_.solve(options); }

  WalledCost cost_{10.0, 5.0};
  double x_ = 0.0;
  SchurLm lm_{[](const double*) { return false; }};
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
  SchurLm lm([](const double*) { return true; });
  lm.add_term(&cost, nullptr, {a, b});
  // A term between two free points.
  EXPECT_THROW(lm.solve({}), std::invalid_argument);
  // With one of them held, the other is eliminated and solved exactly.
  lm.set_constant(b);
  const SchurLmSummary s = lm.solve({});
  EXPECT_TRUE(s.usable);
  EXPECT_NEAR(a[0], -4.0, 1e-6);
  EXPECT_NEAR(a[2], -6.0, 1e-6);
}

TEST(SchurLm, ARemovedTermIsLeftOutOfLaterSolves) {
  WalledCost to_ten(10.0, 100.0), to_zero(0.0, 100.0);
  double x = 3.0;
  SchurLm lm([](const double*) { return false; });
  lm.add_term(&to_ten, nullptr, {&x});
  const int second = lm.add_term(&to_zero, nullptr, {&x});
  EXPECT_EQ(lm.num_terms(), 2);
  EXPECT_TRUE(lm.solve({}).usable);
  EXPECT_NEAR(x, 5.0, 1e-6);  // between the two targets
  lm.remove_term(second);
  lm.remove_term(second);  // removing twice changes nothing
  EXPECT_EQ(lm.num_terms(), 1);
  const double x_before = x;
  const SchurLmSummary s = lm.solve({});
  EXPECT_DOUBLE_EQ(s.initial_cost, 0.5 * (x_before - 10.0) * (x_before - 10.0));  // only the first
  EXPECT_NEAR(x, 10.0, 1e-6);
}

TEST(SchurLm, BlocksAreCheckedWhenAdded) {
  WalledCost cost(1.0, 100.0);
  double x = 0.0, p[3] = {0, 0, 0};
  SchurLm lm([&](const double* b) { return b == p; });
  lm.add_block(&x, 1);
  EXPECT_THROW(lm.add_block(&x, 1), std::invalid_argument);
  EXPECT_TRUE(lm.has_block(&x));
  EXPECT_FALSE(lm.has_block(p));
  SumCost two_blocks;
  EXPECT_THROW(lm.add_term(&two_blocks, nullptr, {p}), std::invalid_argument);
  // A point must be 3 plain doubles.
  lm.add_block(p, 2);
  lm.add_term(&cost, nullptr, {&x});
  EXPECT_THROW(lm.solve({}), std::invalid_argument);
}

}  // namespace
}  // namespace hs
