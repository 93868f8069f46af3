#include "common/eval/align.h"

#include <gtest/gtest.h>

#include "common/core/error.h"
#include "common/eval/metrics.h"
#include "eval_test_util.h"

namespace hs {
namespace {

double max_error(const Trajectory& gt, const Trajectory& est, PoseRelation relation) {
  double m = 0.0;
  for (double v : compute_ape(gt, est, relation).values) m = std::max(m, v);
  return m;
}

TEST(Align, RandomSe3IsRemovedExactly) {
  std::mt19937 rng(7);
  const Trajectory gt = test::figure_eight(200);
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Isometry3d T = test::random_pose(rng, 50.0);
    Trajectory est = test::transformed(gt, T.inverse());
    ASSERT_GT(max_error(gt, est, PoseRelation::kTransPart), 0.1);
    const Sim3 S = compute_alignment(gt, est, AlignMode::kSe3);
    EXPECT_TRUE(S.R.isApprox(T.linear(), 1e-9));
    EXPECT_DOUBLE_EQ(S.s, 1.0);
    apply_alignment(S, est);
    for (PoseRelation r : {PoseRelation::kTransPart, PoseRelation::kFull, PoseRelation::kAngleDeg})
      EXPECT_LT(max_error(gt, est, r), 1e-9) << relation_name(r);
  }
}

TEST(Align, RandomSim3RecoversScale) {
  std::mt19937 rng(11);
  const Trajectory gt = test::figure_eight(150);
  std::uniform_real_distribution<double> scale(0.1, 10.0);
  for (int trial = 0; trial < 10; ++trial) {
    const double s = scale(rng);
    // est = (1/s) * T^-1 * gt: aligning needs scale s.
    Trajectory est = test::transformed(test::transformed(gt, test::random_pose(rng, 20.0)),
                                       Eigen::Isometry3d::Identity(), 1.0 / s);
    const Sim3 S = compute_alignment(gt, est, AlignMode::kSim3);
    EXPECT_NEAR(S.s, s, 1e-9 * s);
    apply_alignment(S, est);
    EXPECT_LT(max_error(gt, est, PoseRelation::kTransPart), 1e-9);
    EXPECT_LT(max_error(gt, est, PoseRelation::kAngleDeg), 1e-9);
  }
}

TEST(Align, ScaleOnlyLeavesRotationAndTranslation) {
  const Trajectory gt = test::figure_eight(100);
  Trajectory est = test::transformed(gt, Eigen::Isometry3d::Identity(), 0.25);
  const Sim3 S = compute_alignment(gt, est, AlignMode::kScale);
  EXPECT_NEAR(S.s, 4.0, 1e-12);
  EXPECT_TRUE(S.R.isIdentity(0.0));
  EXPECT_TRUE(S.t.isZero(0.0));
  apply_alignment(S, est);
  EXPECT_LT(max_error(gt, est, PoseRelation::kTransPart), 1e-12);
}

TEST(Align, OriginMatchesFirstPoses) {
  std::mt19937 rng(3);
  const Trajectory gt = test::figure_eight(50);
  Trajectory est = test::transformed(gt, test::random_pose(rng, 5.0));
  apply_alignment(compute_alignment(gt, est, AlignMode::kOrigin), est);
  EXPECT_TRUE(est.poses[0].T_w_b.isApprox(gt.poses[0].T_w_b, 1e-12));
  EXPECT_LT(max_error(gt, est, PoseRelation::kFull), 1e-9);  // rigid offset: all poses match
}

TEST(Align, UmeyamaNeverReturnsReflection) {
  // A planar point set mirrored through its plane: the best proper rotation is not a reflection.
  std::vector<Eigen::Vector3d> src, dst;
  for (int i = 0; i < 10; ++i) {
    src.emplace_back(std::cos(i), std::sin(2.0 * i), 0.1 * i);
    dst.emplace_back(src.back().x(), src.back().y(), -src.back().z());
  }
  const Sim3 S = umeyama(src, dst, false);
  EXPECT_NEAR(S.R.determinant(), 1.0, 1e-12);
}

TEST(Align, DegenerateConfigurationThrows) {
  std::vector<Eigen::Vector3d> line, other;
  for (int i = 0; i < 10; ++i) {
    line.emplace_back(i, 2.0 * i, 0.0);
    other.emplace_back(i, 0.0, 1.0 * i);
  }
  EXPECT_THROW(umeyama(line, other, false), InputError);
  EXPECT_THROW(umeyama({Eigen::Vector3d::Zero()}, {Eigen::Vector3d::Ones()}, true), InputError);
}

}  // namespace
}  // namespace hs
