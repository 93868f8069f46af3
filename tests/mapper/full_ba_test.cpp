#include "mapper/full_ba.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "tests/mapper/keyframe_test_util.h"

namespace hs {
namespace {

using test::ids;
using test::keyframe;

// Keyframes 0-3 in one world, sharing points 0-5 (5 m ahead of them); 10-11 in another.
KeyframeGraph two_worlds() {
  KeyframeGraph g;
  g.insert(keyframe(0, -1, ids(0, 3)));
  g.insert(keyframe(1, 0, ids(0, 5)));
  g.insert(keyframe(2, 1, ids(2, 5)));
  g.insert(keyframe(3, 2, ids(4, 5)));
  g.insert(keyframe(10, -1, ids(100, 103), 7));
  g.insert(keyframe(11, 10, ids(100, 103), 7));
  return g;
}

std::vector<int64_t> keyframe_ids(const LocalBaInput& in) {
  std::vector<int64_t> out;
  for (const BaKeyframe& k : in.keyframes) out.push_back(k.id);
  std::sort(out.begin(), out.end());
  return out;
}

TEST(FullBa, TheProblemIsTheWholeWorldWithItsImuChain) {
  const KeyframeGraph g = two_worlds();
  WindowInputOptions options;
  const LocalBaInput in = full_ba_input(g, g.world(1), default_gravity_w(), options);
  EXPECT_EQ(keyframe_ids(in), ids(0, 3));
  for (const BaKeyframe& k : in.keyframes) EXPECT_FALSE(k.fixed);  // the BA holds the oldest
  EXPECT_EQ(in.points.size(), 6u);                                 // each seen by two or more
  for (const BaPoint& p : in.points) EXPECT_FALSE(p.fixed);
  EXPECT_EQ(in.imu_factors.size(), 3u);
  EXPECT_EQ(in.gravity.prior_sigma_rad, 0.0);

  // Points farther than the far-point distance from every keyframe seeing them are held, and
  // frozen keyframes (a loaded map in localisation-only mode) too.
  options.fixed_point_distance_m = 4.0;
  const LocalBaInput far =
      full_ba_input(g, g.world(1), default_gravity_w(), options, [](int64_t k) { return k == 0; });
  for (const BaPoint& p : far.points) EXPECT_TRUE(p.fixed) << p.id;
  for (const BaKeyframe& k : far.keyframes) EXPECT_EQ(k.fixed, k.id == 0) << k.id;
  options.fixed_point_distance_m = 6.0;
  for (const BaPoint& p : full_ba_input(g, g.world(1), default_gravity_w(), options).points)
    EXPECT_FALSE(p.fixed) << p.id;
}

Eigen::Isometry3d shift(double x, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, 0.2, 0.0);
  return T;
}

void expect_pose_near(const NavState& a, const Eigen::Isometry3d& b, const char* what) {
  EXPECT_LT((a.p_w_b - b.translation()).norm(), 1e-9) << what;
  EXPECT_LT(Eigen::AngleAxisd(a.T_w_b().linear().transpose() * b.linear()).angle(), 1e-9) << what;
}

// The result comes back to a graph that moved on: a local BA moved keyframe 3 and point 5, and
// keyframe 4 with point 6 arrived. Unchanged ones take the result; the others move with the
// correction of their keyframe, the new keyframe with the newest optimised one's.
TEST(FullBa, AResultAppliedToAGraphThatMovedOnCorrectsWhatChangedSince) {
  KeyframeGraph g = two_worlds();
  const LocalBaInput in = full_ba_input(g, g.world(1), default_gravity_w(), {});
  LocalBaResult result;
  result.keyframes = in.keyframes;
  result.points = in.points;
  std::vector<Eigen::Isometry3d> C(in.keyframes.size());
  for (size_t n = 0; n < in.keyframes.size(); ++n) {
    C[n] = shift(0.01 * in.keyframes[n].id, 0.002 * in.keyframes[n].id);
    result.keyframes[n].state = transformed(in.keyframes[n].state, C[n]);
  }
  for (BaPoint& p : result.points) p.p_w += Eigen::Vector3d(0.0, 0.0, 0.05);
  const auto C_of = [&](int64_t id) {
    for (size_t n = 0; n < in.keyframes.size(); ++n)
      if (in.keyframes[n].id == id) return C[n];
    throw std::runtime_error("no such keyframe");
  };

  NavState moved = g.keyframe(3)->state;
  moved.p_w_b.x() += 0.03;
  g.set_state(3, moved);
  const Eigen::Vector3d p5 = g.point(5)->p_w + Eigen::Vector3d(0.0, 0.01, 0.0);
  g.set_position(5, p5);
  g.insert(keyframe(4, 3, {5, 6}));
  const NavState new_kf = g.keyframe(4)->state;
  const Eigen::Vector3d p6 = g.point(6)->p_w;
  const NavState other_world = g.keyframe(10)->state;
  const Eigen::Vector3d other_point = g.point(100)->p_w;
  const Eigen::Vector3d p0_result = [&] {
    for (const BaPoint& p : result.points)
      if (p.id == 0) return p.p_w;
    throw std::runtime_error("no point 0");
  }();

  const FullBaApplied applied = apply_full_ba(g, in, result);
  EXPECT_EQ(applied.keyframes, 4);
  EXPECT_EQ(applied.keyframes_moved, 1);
  EXPECT_EQ(applied.points, 6);
  EXPECT_EQ(applied.points_moved, 1);

  expect_pose_near(g.keyframe(1)->state, C_of(1) * in.keyframes[1].state.T_w_b(), "unchanged");
  expect_pose_near(g.keyframe(3)->state, C_of(3) * moved.T_w_b(), "moved by a local BA since");
  expect_pose_near(g.keyframe(4)->state, C_of(3) * new_kf.T_w_b(), "added since");
  EXPECT_LT((g.keyframe(4)->state.v_w - C_of(3).linear() * new_kf.v_w).norm(), 1e-9);
  EXPECT_LT((g.point(0)->p_w - p0_result).norm(), 1e-12);
  // Point 5 (moved since) follows its first observer, keyframe 1; point 6 (new) keyframe 4.
  EXPECT_LT((g.point(5)->p_w - C_of(1) * p5).norm(), 1e-9);
  EXPECT_LT((g.point(6)->p_w - C_of(3) * p6).norm(), 1e-9);
  // The other world is not touched.
  EXPECT_EQ(g.keyframe(10)->state.p_w_b, other_world.p_w_b);
  EXPECT_EQ(g.point(100)->p_w, other_point);
}

TEST(FullBa, KeyframesAndPointsRemovedSinceAreSkipped) {
  KeyframeGraph g = two_worlds();
  const LocalBaInput in = full_ba_input(g, g.world(1), default_gravity_w(), {});
  LocalBaResult result;
  result.keyframes = in.keyframes;
  result.points = in.points;
  ASSERT_TRUE(g.remove_keyframe(2));
  ASSERT_TRUE(g.remove_point(4));
  const FullBaApplied applied = apply_full_ba(g, in, result);
  EXPECT_EQ(applied.keyframes, 3);
  EXPECT_EQ(applied.points, 5);
  EXPECT_EQ(g.keyframe(2), nullptr);
  EXPECT_EQ(g.point(4), nullptr);
}

}  // namespace
}  // namespace hs
