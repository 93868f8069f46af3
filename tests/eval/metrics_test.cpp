#include "common/eval/metrics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/core/error.h"
#include "common/eval/stats.h"
#include "eval_test_util.h"

namespace hs {
namespace {

constexpr double kDeg = M_PI / 180.0;

Eigen::Isometry3d pose(double yaw_deg, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_deg * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = t;
  return T;
}

Trajectory from_poses(const std::vector<Eigen::Isometry3d>& poses) {
  Trajectory t;
  for (size_t i = 0; i < poses.size(); ++i) t.poses.push_back({static_cast<int64_t>(i), poses[i]});
  return t;
}

TEST(Stats, MatchesNumpyDefinitions) {
  const Stats s = compute_stats({4.0, 1.0, 3.0, 2.0});
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);                // mean of the two middle values
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(5.0 / 4.0));  // ddof = 0: (2.25+0.25+0.25+2.25)/4
  EXPECT_DOUBLE_EQ(s.sse, 30.0);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(30.0 / 4.0));
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 4.0);
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(compute_stats({5.0, 1.0, 3.0}).median, 3.0);
  EXPECT_THROW(compute_stats({}), InputError);
}

TEST(Ape, KnownOffsetsGiveKnownStatistics) {
  // Offsets of length 0.01, 0.02, 0.03 m cycling over the axes, no alignment:
  // rmse = 0.01 sqrt(14/3), mean = 0.02, median = 0.02, std = 0.01 sqrt(2/3).
  const Trajectory gt = test::figure_eight(300);
  Trajectory est = gt;
  for (size_t i = 0; i < est.poses.size(); ++i)
    est.poses[i].T_w_b.translation()[static_cast<int>(i % 3)] +=
        0.01 * (1 + i % 3) * (i % 2 ? -1 : 1);
  const Stats s = compute_stats(compute_ape(gt, est, PoseRelation::kTransPart).values);
  EXPECT_NEAR(s.rmse, 0.01 * std::sqrt(14.0 / 3.0), 1e-6);
  EXPECT_NEAR(s.mean, 0.02, 1e-6);
  EXPECT_NEAR(s.median, 0.02, 1e-6);
  EXPECT_NEAR(s.std, 0.01 * std::sqrt(2.0 / 3.0), 1e-6);
  EXPECT_NEAR(s.max, 0.03, 1e-9);
  EXPECT_NEAR(s.min, 0.01, 1e-9);
  // Position noise does not touch orientation.
  EXPECT_LT(compute_stats(compute_ape(gt, est, PoseRelation::kAngleDeg).values).max, 1e-9);
}

TEST(Ape, RelationsOfOneHandComputedPose) {
  // P = (Rz(30 deg), (1, 0.5, 0)), Q = identity: E = P^-1 Q has |t| = |(1, 0.5, 0)|,
  // |R - I|_F^2 = 4 (1 - cos 30 deg), full = sqrt of the sum of both squares.
  const Trajectory gt = from_poses({Eigen::Isometry3d::Identity()});
  const Trajectory est = from_poses({pose(30, {1, 0.5, 0})});
  const double rot_part = std::sqrt(4.0 * (1.0 - std::cos(30 * kDeg)));
  auto ape = [&](PoseRelation r) { return compute_ape(gt, est, r).values.at(0); };
  EXPECT_NEAR(ape(PoseRelation::kTransPart), std::sqrt(1.25), 1e-12);
  EXPECT_NEAR(ape(PoseRelation::kRotPart), rot_part, 1e-12);
  EXPECT_NEAR(ape(PoseRelation::kFull), std::sqrt(rot_part * rot_part + 1.25), 1e-12);
  EXPECT_NEAR(ape(PoseRelation::kAngleDeg), 30.0, 1e-12);
  EXPECT_NEAR(ape(PoseRelation::kAngleRad), 30 * kDeg, 1e-12);
}

// Ground truth: straight 1 m, a 90 degree left turn, then 1 m along the new heading.
// Estimate: first step 1.1 m; turns 100 degrees; last step 1.2 m.
class HandRpe : public ::testing::Test {
 protected:
  const Trajectory gt = from_poses(
      {pose(0, {0, 0, 0}), pose(0, {1, 0, 0}), pose(90, {1, 1, 0}), pose(90, {1, 2, 0})});
  const Trajectory est = from_poses(
      {pose(0, {0, 0, 0}), pose(0, {1.1, 0, 0}), pose(100, {1.1, 1, 0}), pose(100, {1.1, 2.2, 0})});
};

TEST_F(HandRpe, ConsecutiveFramePairs) {
  const std::vector<IndexPair> pairs = rpe_pairs(est, 1, DeltaUnit::kFrames, false);
  ASSERT_EQ(pairs, (std::vector<IndexPair>{{0, 1}, {1, 2}, {2, 3}}));
  const ErrorSeries trans = compute_rpe(gt, est, pairs, PoseRelation::kTransPart);
  const ErrorSeries rot = compute_rpe(gt, est, pairs, PoseRelation::kAngleDeg);
  // (0,1): relative motions (I, 1 m) vs (I, 1.1 m): E = (I, 0.1 m).
  EXPECT_NEAR(trans.values[0], 0.1, 1e-12);
  EXPECT_NEAR(rot.values[0], 0.0, 1e-12);
  // (1,2): (Rz90, (0,1,0)) vs (Rz100, (0,1,0)): E = (Rz10, 0).
  EXPECT_NEAR(trans.values[1], 0.0, 1e-12);
  EXPECT_NEAR(rot.values[1], 10.0, 1e-12);
  // (2,3): gt moves (1,0,0) in its frame; est moves Rz100^T (0,1.2,0) = 1.2 (sin100, cos100, 0):
  // |E_t|^2 = (1.2 sin100 - 1)^2 + (1.2 cos100)^2 = 2.44 - 2.4 sin100 = 2.44 - 2.4 cos10.
  EXPECT_NEAR(trans.values[2], std::sqrt(2.44 - 2.4 * std::cos(10 * kDeg)), 1e-12);
  EXPECT_NEAR(rot.values[2], 0.0, 1e-12);
  EXPECT_EQ(trans.t_ns, (std::vector<int64_t>{1, 2, 3}));
}

TEST_F(HandRpe, DeltaTwoFrames) {
  // Consecutive: ids 0, 2 -> one pair; (Rz90,(1,1,0)) vs (Rz100,(1.1,1,0)): E = (Rz10, 0.1 m).
  const std::vector<IndexPair> pairs = rpe_pairs(est, 2, DeltaUnit::kFrames, false);
  ASSERT_EQ(pairs, (std::vector<IndexPair>{{0, 2}}));
  EXPECT_NEAR(compute_rpe(gt, est, pairs, PoseRelation::kTransPart).values[0], 0.1, 1e-12);
  EXPECT_NEAR(compute_rpe(gt, est, pairs, PoseRelation::kAngleDeg).values[0], 10.0, 1e-12);
  EXPECT_EQ(rpe_pairs(est, 2, DeltaUnit::kFrames, true), (std::vector<IndexPair>{{0, 2}, {1, 3}}));
  EXPECT_THROW(rpe_pairs(est, 4, DeltaUnit::kFrames, false), InputError);
  EXPECT_THROW(rpe_pairs(est, 1.5, DeltaUnit::kFrames, false), InputError);
}

TEST(RpePairs, FramesStepThroughTheTrajectory) {
  const Trajectory t = test::figure_eight(10);
  EXPECT_EQ(rpe_pairs(t, 3, DeltaUnit::kFrames, false),
            (std::vector<IndexPair>{{0, 3}, {3, 6}, {6, 9}}));
  EXPECT_EQ(rpe_pairs(t, 3, DeltaUnit::kFrames, true).size(), 7u);
}

TEST(RpePairs, MetresFollowTravelledPath) {
  // 0.5 m steps along x: the path reaches 1 m at poses 2, 4, 6, 8.
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < 9; ++i) poses.push_back(pose(0, {0.5 * i, 0, 0}));
  const Trajectory t = from_poses(poses);
  EXPECT_EQ(rpe_pairs(t, 1.0, DeltaUnit::kMeters, false),
            (std::vector<IndexPair>{{2, 4}, {4, 6}, {6, 8}}));
  const std::vector<IndexPair> all = rpe_pairs(t, 1.0, DeltaUnit::kMeters, true);
  ASSERT_EQ(all.size(), 7u);
  for (const auto& [i, j] : all) EXPECT_EQ(j, i + 2);
  EXPECT_THROW(rpe_pairs(t, 10.0, DeltaUnit::kMeters, false), InputError);
}

TEST(RpePairs, MetresAllPairsMatchesExhaustiveArgmin) {
  // Random steps including standstills (equal path lengths exercise the tie rule).
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> step(0.0, 0.3);
  std::vector<Eigen::Isometry3d> poses;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int i = 0; i < 300; ++i) {
    if (i % 7 != 0) p.x() += step(rng);
    poses.push_back(pose(0, p));
  }
  const Trajectory t = from_poses(poses);
  const double delta = 2.0, tol = 0.1 * delta;
  std::vector<IndexPair> expected;
  for (size_t i = 0; i + 1 < poses.size(); ++i) {
    size_t best = i + 1;
    auto err = [&](size_t j) {
      return std::abs(poses[j].translation().x() - poses[i].translation().x() - delta);
    };
    for (size_t j = i + 1; j < poses.size(); ++j)
      if (err(j) < err(best)) best = j;
    if (err(best) <= tol) expected.emplace_back(i, best);
  }
  ASSERT_GT(expected.size(), 200u);
  EXPECT_EQ(rpe_pairs(t, delta, DeltaUnit::kMeters, true), expected);
}

TEST(PoseRelation, ParsesEvoNamesAndAliases) {
  EXPECT_EQ(parse_pose_relation("trans_part"), PoseRelation::kTransPart);
  EXPECT_EQ(parse_pose_relation("trans"), PoseRelation::kTransPart);
  EXPECT_EQ(parse_pose_relation("rot_angle_deg"), PoseRelation::kAngleDeg);
  EXPECT_EQ(parse_pose_relation("full"), PoseRelation::kFull);
  EXPECT_THROW(parse_pose_relation("bogus"), InputError);
}

}  // namespace
}  // namespace hs
