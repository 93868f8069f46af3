#include "common/eval/associate.h"

#include <gtest/gtest.h>

#include <vector>

#include "common/core/error.h"

namespace hs {
namespace {

Trajectory stamps(const std::vector<int64_t>& t_ns) {
  Trajectory t;
  for (int64_t s : t_ns) {
    StampedPose p;
    p.t_ns = s;
    p.T_w_b.translation().x() = static_cast<double>(s);  // identifies the pose
    t.poses.push_back(p);
  }
  return t;
}

std::vector<int64_t> times(const Trajectory& t) {
  std::vector<int64_t> out;
  for (const StampedPose& p : t.poses) out.push_back(p.t_ns);
  return out;
}

constexpr int64_t kMs = 1'000'000;

TEST(Associate, NearestWithinMaxDiff) {
  const Trajectory gt = stamps({0, 10 * kMs, 20 * kMs, 30 * kMs, 40 * kMs});
  const Trajectory est = stamps({4 * kMs, 16 * kMs, 33 * kMs, 70 * kMs});
  const Association a = associate(gt, est, 5 * kMs);
  EXPECT_EQ(times(a.est), (std::vector<int64_t>{4 * kMs, 16 * kMs, 33 * kMs}));
  EXPECT_EQ(times(a.gt), (std::vector<int64_t>{0, 20 * kMs, 30 * kMs}));
  // A tighter limit drops the two pairs 4 ms apart.
  EXPECT_EQ(times(associate(gt, est, 3 * kMs).est), (std::vector<int64_t>{33 * kMs}));
  // The limit is inclusive.
  EXPECT_EQ(associate(gt, est, 4 * kMs).est.poses.size(), 3u);
}

TEST(Associate, TieTakesEarlierPose) {
  const Association a = associate(stamps({0, 10 * kMs}), stamps({5 * kMs}), 5 * kMs);
  ASSERT_EQ(a.gt.poses.size(), 1u);
  EXPECT_EQ(a.gt.poses[0].t_ns, 0);
}

TEST(Associate, OffsetIsAddedToEstimateStamps) {
  const Trajectory gt = stamps({100 * kMs, 110 * kMs, 120 * kMs});
  const Trajectory est = stamps({0, 10 * kMs, 20 * kMs});
  EXPECT_THROW(associate(gt, est, 10 * kMs), InputError);
  const Association a = associate(gt, est, 1 * kMs, 101 * kMs);
  EXPECT_EQ(times(a.gt), (std::vector<int64_t>{100 * kMs, 110 * kMs, 120 * kMs}));
  EXPECT_EQ(times(a.est), (std::vector<int64_t>{0, 10 * kMs, 20 * kMs}));  // own stamps kept
}

TEST(Associate, LongerEstimateIsSearchedFromGroundTruth) {
  // evo iterates over the shorter trajectory: each ground-truth pose takes its nearest estimate.
  const Trajectory gt = stamps({10 * kMs, 20 * kMs});
  const Trajectory est = stamps({8 * kMs, 9 * kMs, 12 * kMs, 19 * kMs, 25 * kMs});
  const Association a = associate(gt, est, 5 * kMs, 1 * kMs);  // est + 1 ms: 9,10,13,20,26
  EXPECT_EQ(times(a.gt), (std::vector<int64_t>{10 * kMs, 20 * kMs}));
  EXPECT_EQ(times(a.est), (std::vector<int64_t>{9 * kMs, 19 * kMs}));
}

TEST(Associate, SparseEstimateMayReuseGroundTruthPose) {
  const Trajectory gt = stamps({0, 100 * kMs, 200 * kMs});
  const Association a = associate(gt, stamps({98 * kMs, 102 * kMs}), 5 * kMs);
  EXPECT_EQ(times(a.gt), (std::vector<int64_t>{100 * kMs, 100 * kMs}));
}

}  // namespace
}  // namespace hs
