#include "tracker/keyframe_policy.h"

#include <gtest/gtest.h>

namespace hs {
namespace {

TEST(KeyframePolicy, PoseChangeIsFrobeniusNormOfRelativeTransformMinusIdentity) {
  Eigen::Isometry3d a = Eigen::Isometry3d::Identity(), b = Eigen::Isometry3d::Identity();
  b.translation() = Eigen::Vector3d(0.03, 0.04, 0.0);
  EXPECT_NEAR(pose_change_norm(a, b), 0.05, 1e-12);
  b.setIdentity();
  b.rotate(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()));
  // ||R - I||_F = 2 sqrt(2) sin(theta / 2) for a rotation by theta.
  EXPECT_NEAR(pose_change_norm(a, b), 2.0 * std::sqrt(2.0) * std::sin(0.05), 1e-12);
}

TEST(KeyframePolicy, MeanParallax) {
  EXPECT_DOUBLE_EQ(mean_parallax({{0, 0}, {10, 10}}, {{3, 4}, {10, 20}}), 7.5);
  EXPECT_DOUBLE_EQ(mean_parallax({}, {}), 0.0);
}

TEST(KeyframePolicy, EachCriterionFires) {
  const KeyframePolicyOptions o;
  const int64_t ok_interval = 200'000'000;
  const double big_change = 1.2 * o.pose_change, small_change = 0.5 * o.pose_change;
  const double big_parallax = 1.2 * o.parallax_px, small_parallax = 0.5 * o.parallax_px;
  EXPECT_FALSE(decide_keyframe(o, small_change, small_parallax, 200, ok_interval).is_keyframe);
  EXPECT_EQ(decide_keyframe(o, big_change, small_parallax, 200, ok_interval).reason, "pose change");
  EXPECT_EQ(decide_keyframe(o, small_change, big_parallax, 200, ok_interval).reason, "parallax");
  // Too few tracked: even right away.
  EXPECT_TRUE(decide_keyframe(o, small_change, small_parallax, 10, 0).is_keyframe);
  EXPECT_FALSE(decide_keyframe(o, big_change, big_parallax, 200, 0).is_keyframe);  // too soon
  EXPECT_EQ(decide_keyframe(o, 0.0, 0.0, 200, o.max_interval_ns).reason, "interval");
}

}  // namespace
}  // namespace hs
