// Closing a loop on a keyframe graph: a drive round a 20 m square whose keyframes drifted (yaw and
// scale) meets its start again; the pose graph puts the keyframes back near the truth, turns
// their velocities with them, and every point keeps its place relative to its first observer.
#include "mapper/loop_closing.h"

#include <gtest/gtest.h>

namespace hs {
namespace {

Eigen::Isometry3d pose_at(int k, double yaw_drift_per_step, double scale) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int i = 0; i < k; ++i) {
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    step.translation() = Eigen::Vector3d(1.0 * scale, 0, 0);
    const double turn = (i % 20 == 19 ? M_PI / 2 : 0.0) + yaw_drift_per_step;
    step.linear() = Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T = T * step;
  }
  return T;
}

class LoopClosingTest : public ::testing::Test {
 protected:
  void SetUp() override {
    for (int k = 0; k < 80; ++k) {
      MapperKeyframe kf;
      kf.id = k;
      kf.prev_id = k - 1;
      kf.state.t_ns = 1'000'000'000LL * (k + 1);
      const Eigen::Isometry3d T = pose_at(k, 0.1 * M_PI / 180, 1.01);
      kf.state.p_w_b = T.translation();
      kf.state.q_w_b = Eigen::Quaterniond(T.linear());
      kf.state.v_w = T.linear() * Eigen::Vector3d(2, 0, 0);
      MapperKeypoint kp;
      kp.point_id = 1000 + k;
      kf.keypoints.push_back(kp);
      kf.descriptors.emplace_back();
      kf.point_positions[kp.point_id] = T * Eigen::Vector3d(3, 1, 0.5);
      graph_.insert(kf);
    }
  }
  KeyframeGraph graph_;
};

TEST_F(LoopClosingTest, TheDriftedSquareIsPulledBackAndPointsFollowTheirKeyframes) {
  LoopFound loop;
  loop.query = 79;
  loop.candidate = 0;
  loop.T_c_q = pose_at(0, 0, 1).inverse() * pose_at(79, 0, 1);  // as measured: the truth
  const double before = (graph_.keyframe(79)->state.p_w_b - pose_at(79, 0, 1).translation()).norm();
  const Eigen::Vector3d v_before = graph_.keyframe(60)->state.v_w;
  const LoopClosureStats stats = close_loop(graph_, {loop}, {});
  EXPECT_EQ(stats.keyframes, 80);
  EXPECT_EQ(stats.edges, 80);  // the chain and the loop (no covisibility: no shared points)
  EXPECT_EQ(stats.points_moved, 80);
  EXPECT_GT(before, 1.0);
  const double after = (graph_.keyframe(79)->state.p_w_b - pose_at(79, 0, 1).translation()).norm();
  EXPECT_LT(after, 0.1 * before);
  EXPECT_GT(stats.max_shift_m, 0.5 * before);
  for (int k = 0; k < 80; ++k) {
    const MapperKeyframe& kf = *graph_.keyframe(k);
    const Eigen::Vector3d p_b = kf.state.T_w_b().inverse() * graph_.point(1000 + k)->p_w;
    EXPECT_LT((p_b - Eigen::Vector3d(3, 1, 0.5)).norm(), 1e-9) << "point of keyframe " << k;
    EXPECT_NEAR(
        (kf.state.T_w_b().linear().transpose() * kf.state.v_w - Eigen::Vector3d(2, 0, 0)).norm(),
        0.0, 1e-9)
        << "velocity of keyframe " << k;
  }
  EXPECT_GT((graph_.keyframe(60)->state.v_w - v_before).norm(), 1e-3);  // turned
  EXPECT_TRUE(graph_.keyframe(0)->state.T_w_b().isApprox(pose_at(0, 0.1 * M_PI / 180, 1.01)));
}

}  // namespace
}  // namespace hs
