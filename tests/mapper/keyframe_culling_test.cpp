#include "mapper/keyframe_culling.h"

#include <gtest/gtest.h>

#include <vector>

#include "tests/mapper/keyframe_test_util.h"

namespace hs {
namespace {

using test::ids;
using test::keyframe;

// A chain of keyframes 0..n-1 that all see points 0..19 at the given octaves.
KeyframeGraph same_view(const std::vector<int8_t>& octaves) {
  KeyframeGraph g;
  for (size_t i = 0; i < octaves.size(); ++i) {
    const auto id = static_cast<int64_t>(i);
    g.insert(keyframe(id, id - 1, ids(0, 19), 0, octaves[i]));
  }
  return g;
}

TEST(KeyframeCulling, ThinsKeyframesThatSeeTheSamePoints) {
  KeyframeGraph g = same_view({0, 0, 0, 0, 0});
  CullingOptions options;
  options.keep_recent = 1;
  // 0 and 1 each have three other observers left; after them, 2 and 3 would not.
  const std::vector<int64_t> redundant = redundant_keyframes(g, g.keyframe_ids(), options);
  EXPECT_EQ(redundant, (std::vector<int64_t>{0, 1}));
  for (int64_t id : redundant) g.remove_keyframe(id);
  EXPECT_TRUE(redundant_keyframes(g, g.keyframe_ids(), options).empty());
  for (int64_t p = 0; p < 20; ++p) EXPECT_EQ(g.point(p)->observations.size(), 3u);
}

TEST(KeyframeCulling, NeverReturnsTheNewestKeyframes) {
  const KeyframeGraph g = same_view({0, 0, 0, 0, 0});
  CullingOptions options;
  options.keep_recent = 4;
  EXPECT_EQ(redundant_keyframes(g, g.keyframe_ids(), options), (std::vector<int64_t>{0}));
}

TEST(KeyframeCulling, ObserversMustSeeAtTheSameOrAFinerScale) {
  const KeyframeGraph g = same_view({0, 2, 2, 2});
  CullingOptions options;
  options.keep_recent = 0;
  // Keyframe 0 is the only fine view: kept. Keyframe 1 is covered by 0, 2 and 3.
  EXPECT_EQ(redundant_keyframes(g, g.keyframe_ids(), options), (std::vector<int64_t>{1}));
  options.octave_slack = 2;  // coarser views count too
  EXPECT_EQ(redundant_keyframes(g, g.keyframe_ids(), options), (std::vector<int64_t>{0}));
}

TEST(KeyframeCulling, NeedsTheRatioOfPointsSeenElsewhere) {
  KeyframeGraph g;
  g.insert(keyframe(0, -1, ids(0, 19)));
  for (int64_t i = 1; i <= 3; ++i) g.insert(keyframe(i, i - 1, ids(0, 16)));  // 17 of 20
  CullingOptions options;
  options.keep_recent = 0;
  EXPECT_TRUE(redundant_keyframes(g, {0}, options).empty());
  options.redundant_ratio = 0.8;
  EXPECT_EQ(redundant_keyframes(g, {0}, options), (std::vector<int64_t>{0}));
}

TEST(KeyframeCulling, KeepsImuIntervalsShort) {
  KeyframeGraph g;
  g.insert(keyframe(0, -1, ids(0, 29)));  // sees 10 points nobody else does: never redundant
  for (int64_t i = 1; i <= 4; ++i) g.insert(keyframe(i, i - 1, ids(0, 19)));
  CullingOptions options;
  options.keep_recent = 1;
  EXPECT_EQ(redundant_keyframes(g, g.keyframe_ids(), options), (std::vector<int64_t>{1, 2}));
  // Keyframes are 100 ms apart: removing any one joins two intervals into 200 ms.
  options.max_imu_span_ns = 150'000'000;
  EXPECT_TRUE(redundant_keyframes(g, g.keyframe_ids(), options).empty());
  // Within 250 ms: removing 1 joins 0..2; then 2 would join 0..3 (300 ms), so 3 goes instead.
  options.max_imu_span_ns = 250'000'000;
  EXPECT_EQ(redundant_keyframes(g, g.keyframe_ids(), options), (std::vector<int64_t>{1, 3}));
}

}  // namespace
}  // namespace hs
