#include "mapper/inertial_refinement.h"

#include <gtest/gtest.h>

#include "tests/mapper/keyframe_test_util.h"

namespace hs {
namespace {

using test::ids;

// A chain 1 <- 2 <- ... <- n of keyframes with IMU between them, then 100 starting a new map
// (no IMU link back).
KeyframeGraph chain(int n) {
  KeyframeGraph g;
  for (int k = 1; k <= n; ++k)
    g.insert(test::keyframe(k, k == 1 ? -1 : k - 1, ids(10 * k, 10 * k + 9)));
  g.insert(test::keyframe(100, -1, ids(1000, 1009), 1));
  return g;
}

TEST(InertialRefinement, TakesTheNewestStretchOfTheChainWithPosesHeld) {
  const KeyframeGraph g = chain(8);
  InertialRefinementOptions o;
  o.min_keyframes = 3;
  o.max_keyframes = 5;
  int skipped = 0;
  const Eigen::Vector3d g_w(0.1, 0.0, -9.8);
  const LocalBaInput in = inertial_refinement_input(g, 8, g_w, o, WindowInputOptions{}, &skipped);
  ASSERT_EQ(in.keyframes.size(), 5u);
  for (size_t k = 0; k < in.keyframes.size(); ++k) {
    EXPECT_EQ(in.keyframes[k].id, static_cast<int64_t>(4 + k));
    EXPECT_TRUE(in.keyframes[k].pose_fixed);
    EXPECT_FALSE(in.keyframes[k].fixed);
  }
  ASSERT_EQ(in.imu_factors.size(), 4u);
  EXPECT_EQ(in.imu_factors.front().keyframe_i, 4);
  EXPECT_EQ(in.imu_factors.back().keyframe_j, 8);
  EXPECT_TRUE(in.points.empty());
  EXPECT_TRUE(in.observations.empty());
  EXPECT_EQ(in.gravity.g_w, g_w);
  EXPECT_EQ(in.gravity.prior_sigma_rad, o.gravity_prior_sigma_rad);
  EXPECT_EQ(skipped, 0);
}

TEST(InertialRefinement, TooShortAChainIsNotRefined) {
  const KeyframeGraph g = chain(8);
  InertialRefinementOptions o;
  o.min_keyframes = 9;
  int skipped = 0;
  EXPECT_TRUE(
      inertial_refinement_input(g, 8, default_gravity_w(), o, {}, &skipped).keyframes.empty());
  // A new map id breaks the chain: keyframe 100 stands alone.
  o.min_keyframes = 2;
  EXPECT_TRUE(
      inertial_refinement_input(g, 100, default_gravity_w(), o, {}, &skipped).keyframes.empty());
}

}  // namespace
}  // namespace hs
