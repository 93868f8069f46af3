// POSE_IMU propagation on the receive side, against a closed-form motion.
#include "tracker/node/pose_imu.h"

#include <gtest/gtest.h>

#include "tests/imu/analytic_motion.h"

namespace hs {
namespace {

constexpr int64_t kPeriodNs = 5'000'000;  // 200 Hz
constexpr int64_t kKeepNs = 1'000'000'000;

PoseAnchor anchor_at(const test::AnalyticMotion& m, int64_t t_ns, const ImuBias& bias) {
  PoseAnchor a;
  a.nav = m.state(t_ns, bias);
  a.map_id = 3;
  return a;
}

TEST(PoseImuPropagator, FollowsTheMotionFromTheLatestAnchor) {
  const test::AnalyticMotion motion;
  ImuBias bias;
  bias.gyro = Eigen::Vector3d(0.01, -0.02, 0.005);
  bias.accel = Eigen::Vector3d(0.1, 0.05, -0.08);
  PoseImuPropagator prop({}, kKeepNs);
  const int64_t t0 = 2'000'000'000;
  EXPECT_FALSE(prop.propagate(t0));  // no anchor yet
  for (const ImuSample& s : motion.samples(t0 - 100'000'000, t0, kPeriodNs, bias)) prop.add(s);
  prop.set_anchor(anchor_at(motion, t0, bias));
  EXPECT_LE(prop.buffered(), 2u);  // only what interpolates the anchor time is kept
  EXPECT_FALSE(prop.propagate(t0 - kPeriodNs));

  for (const ImuSample& s : motion.samples(t0 + kPeriodNs, t0 + 200'000'000, kPeriodNs, bias)) {
    prop.add(s);
    const std::optional<NavState> x = prop.propagate(s.t_ns);
    ASSERT_TRUE(x);
    const NavState truth = motion.state(s.t_ns);
    EXPECT_EQ(x->t_ns, s.t_ns);
    EXPECT_LT((x->p_w_b - truth.p_w_b).norm(), 1e-3) << s.t_ns;
    EXPECT_LT((x->v_w - truth.v_w).norm(), 1e-2) << s.t_ns;
    EXPECT_LT(x->q_w_b.angularDistance(truth.q_w_b), 1e-3) << s.t_ns;
  }
  // 0.2 s of motion: the propagation really moved the state (not the anchor held).
  EXPECT_GT((motion.p(2.2) - motion.p(2.0)).norm(), 0.1);

  // Samples going back in time are ignored; a stale anchor (> keep_ns) propagates nothing.
  const size_t n = prop.buffered();
  prop.add(motion.sample(t0));
  EXPECT_EQ(prop.buffered(), n);
  for (const ImuSample& s : motion.samples(t0 + 205'000'000, t0 + kKeepNs, kPeriodNs)) prop.add(s);
  EXPECT_TRUE(prop.propagate(t0 + kKeepNs));
  prop.add(motion.sample(t0 + kKeepNs + kPeriodNs));
  EXPECT_FALSE(prop.propagate(t0 + kKeepNs + kPeriodNs));
  EXPECT_EQ(prop.anchor()->map_id, 3);
}

}  // namespace
}  // namespace hs
