#include "mapper/keyframe_graph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "tests/mapper/keyframe_test_util.h"

namespace hs {
namespace {

using test::ids;
using test::keyframe;
using test::keyframe_time;

int count_shared(const std::vector<int64_t>& a, const std::vector<int64_t>& b) {
  return static_cast<int>(std::count_if(
      a.begin(), a.end(), [&](int64_t x) { return std::count(b.begin(), b.end(), x); }));
}

TEST(KeyframeGraph, CovisibilityCountsSharedPoints) {
  const auto p0 = ids(0, 9), p1 = ids(5, 14), p2 = ids(8, 19);
  KeyframeGraph g;
  g.insert(keyframe(0, -1, p0));
  g.insert(keyframe(1, 0, p1));
  g.insert(keyframe(2, 1, p2));
  EXPECT_EQ(g.num_keyframes(), 3u);
  EXPECT_EQ(g.num_points(), 20u);
  EXPECT_EQ(g.shared_points(0, 1), count_shared(p0, p1));
  EXPECT_EQ(g.shared_points(1, 0), count_shared(p0, p1));
  EXPECT_EQ(g.shared_points(0, 2), count_shared(p0, p2));
  EXPECT_EQ(g.shared_points(1, 2), count_shared(p1, p2));
  EXPECT_EQ(g.most_covisible(1, 2), (std::vector<int64_t>{2, 0}));  // 7 shared, then 5
  EXPECT_EQ(g.most_covisible(0, 1), (std::vector<int64_t>{1}));
  const MapperPoint* p = g.point(8);
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->observations.size(), 3u);
  EXPECT_EQ(p->first_keyframe_id, 0);
  EXPECT_EQ(g.counters().inserted, 3);
  EXPECT_THROW(g.most_covisible(7, 1), std::out_of_range);
}

TEST(KeyframeGraph, KnownPointsKeepTheMappersPosition) {
  KeyframeGraph g;
  g.insert(keyframe(0, -1, {3, 4}));
  const Eigen::Vector3d first = g.point(3)->p_w;
  hsslam::keyframe_t later = test::keyframe_msg(1, 0, {3, 4});
  later.points[0].p_w[0] += 1.0;  // the tracker's newer estimate of point 3
  g.insert(keyframe_from_msg(later, "KEYFRAME"));
  EXPECT_EQ(g.point(3)->p_w, first);
  const Eigen::Vector3d refined(1.0, 2.0, 3.0);
  g.set_position(3, refined);
  g.insert(keyframe_from_msg(test::keyframe_msg(2, 1, {3}), "KEYFRAME"));
  EXPECT_EQ(g.point(3)->p_w, refined);
  EXPECT_TRUE(g.keyframe(2)->point_positions.empty());  // one source of truth: the store
}

TEST(KeyframeGraph, OptimisedStatesAreWrittenBack) {
  KeyframeGraph g;
  g.insert(keyframe(0, -1, {1}));
  NavState x = g.keyframe(0)->state;
  x.p_w_b = Eigen::Vector3d(4.0, 5.0, 6.0);
  g.set_state(0, x);
  EXPECT_EQ(g.keyframe(0)->state.p_w_b, x.p_w_b);
  x.t_ns += 1;  // a state of another time cannot replace the keyframe's
  EXPECT_THROW(g.set_state(0, x), std::invalid_argument);
  EXPECT_THROW(g.set_state(3, x), std::out_of_range);
  EXPECT_THROW(g.set_position(2, x.p_w_b), std::out_of_range);
}

TEST(KeyframeGraph, RemovingAKeyframeUpdatesWeightsAndDropsOrphanPoints) {
  auto p1 = ids(5, 14);
  p1.push_back(50);  // seen by keyframe 1 only
  KeyframeGraph g;
  g.insert(keyframe(0, -1, ids(0, 9)));
  g.insert(keyframe(1, 0, p1));
  g.insert(keyframe(2, 1, ids(8, 19)));
  const int shared_02 = g.shared_points(0, 2);
  ASSERT_TRUE(g.remove_keyframe(1));
  EXPECT_FALSE(g.remove_keyframe(1));
  EXPECT_EQ(g.keyframe(1), nullptr);
  EXPECT_EQ(g.point(50), nullptr);
  EXPECT_EQ(g.num_points(), 20u);
  EXPECT_EQ(g.shared_points(0, 2), shared_02);
  EXPECT_EQ(g.most_covisible(0, 5), (std::vector<int64_t>{2}));
  EXPECT_EQ(g.most_covisible(2, 5), (std::vector<int64_t>{0}));
  EXPECT_EQ(g.point(8)->observations.size(), 2u);
  EXPECT_EQ(g.point(6)->observations.size(), 1u);
}

TEST(KeyframeGraph, TheMappersOwnPointsTakeFreeKeypointsAndIdsOfTheirOwn) {
  KeyframeGraph g;
  g.insert(keyframe(0, -1, ids(0, 4)));  // keypoint 5 of each is free
  g.insert(keyframe(1, 0, ids(3, 7)));
  g.insert(keyframe(2, 1, ids(20, 21)));
  ASSERT_EQ(g.shared_points(0, 1), 2);
  ASSERT_EQ(g.shared_points(0, 2), 0);
  const int64_t id = g.add_point(Eigen::Vector3d(1, 2, 3), {{0, 5}, {1, 5}, {2, 2}});
  EXPECT_TRUE(mapper_made_point(id));
  EXPECT_FALSE(mapper_made_point(7));
  EXPECT_EQ(g.shared_points(0, 1), 3);
  EXPECT_EQ(g.shared_points(0, 2), 1);
  EXPECT_EQ(g.shared_points(1, 2), 1);
  EXPECT_EQ(g.keyframe(1)->keypoints[5].point_id, id);
  ASSERT_NE(g.point(id), nullptr);
  EXPECT_EQ(g.point(id)->observations.size(), 3u);
  EXPECT_EQ(g.point(id)->p_w, Eigen::Vector3d(1, 2, 3));
  // A keypoint that sees a point already is refused, and nothing changes.
  EXPECT_THROW(g.add_point(Eigen::Vector3d::Zero(), {{2, 0}, {0, 0}}), std::invalid_argument);
  EXPECT_EQ(g.shared_points(0, 2), 1);
  EXPECT_EQ(g.num_points(), 11u);
  g.insert(keyframe(3, 2, {30}));
  EXPECT_EQ(g.add_point(Eigen::Vector3d::Zero(), {{3, 1}}), id + 1) << "the failed call took no id";
}

TEST(KeyframeGraph, RemovingAPointUpdatesWeightsAndKeypoints) {
  KeyframeGraph g;
  g.insert(keyframe(0, -1, ids(0, 9)));
  g.insert(keyframe(1, 0, ids(5, 14)));
  g.insert(keyframe(2, 1, ids(8, 19)));
  const int s01 = g.shared_points(0, 1), s02 = g.shared_points(0, 2), s12 = g.shared_points(1, 2);
  ASSERT_TRUE(g.remove_point(9));  // seen by all three
  EXPECT_FALSE(g.remove_point(9));
  EXPECT_EQ(g.shared_points(0, 1), s01 - 1);
  EXPECT_EQ(g.shared_points(0, 2), s02 - 1);
  EXPECT_EQ(g.shared_points(1, 2), s12 - 1);
  for (int64_t k : {0, 1, 2})
    for (const MapperKeypoint& kp : g.keyframe(k)->keypoints) EXPECT_NE(kp.point_id, 9);
  // Weights that reach zero disappear.
  ASSERT_TRUE(g.remove_point(8));
  EXPECT_EQ(g.shared_points(0, 2), 0);
  EXPECT_EQ(g.most_covisible(0, 5), (std::vector<int64_t>{1}));
}

// Keyframe i sees points 10i..10i+14: five shared with each neighbour, none further.
KeyframeGraph strip_of_keyframes(const KeyframeGraphOptions& options, int64_t n) {
  KeyframeGraph g(options);
  for (int64_t i = 0; i < n; ++i) g.insert(keyframe(i, i - 1, ids(10 * i, 10 * i + 14)));
  return g;
}

TEST(KeyframeGraph, LocalWindowHoldsTheCovisibleSetAndFixesTheOtherObservers) {
  KeyframeGraphOptions options;
  options.window_covisible = 2;
  const LocalWindow w = strip_of_keyframes(options, 6).local_window(2);
  EXPECT_EQ(w.keyframes, (std::vector<int64_t>{1, 2, 3}));
  EXPECT_EQ(w.points, ids(10, 44));
  EXPECT_EQ(w.fixed_keyframes, (std::vector<int64_t>{0, 4}));  // not 5: it sees none of them

  options.window_min_shared = 6;  // no neighbour shares that many
  const LocalWindow alone = strip_of_keyframes(options, 6).local_window(2);
  EXPECT_EQ(alone.keyframes, (std::vector<int64_t>{2}));
  EXPECT_EQ(alone.points, ids(20, 34));
  EXPECT_EQ(alone.fixed_keyframes, (std::vector<int64_t>{1, 3}));
}

TEST(KeyframeGraph, FixedKeyframesAreCappedToThoseSeeingMostOfTheWindow) {
  const auto graph = [](size_t max_fixed) {
    KeyframeGraphOptions options;
    options.window_covisible = 0;  // the window is keyframe 10 alone
    options.max_fixed_keyframes = max_fixed;
    KeyframeGraph g(options);
    g.insert(keyframe(1, -1, ids(0, 2)));  // sees 3 of the window's points
    g.insert(keyframe(2, -1, ids(0, 9)));  // 10
    g.insert(keyframe(3, -1, ids(0, 5)));  // 6
    g.insert(keyframe(10, -1, ids(0, 19)));
    return g;
  };
  EXPECT_EQ(graph(0).local_window(10).fixed_keyframes, (std::vector<int64_t>{1, 2, 3}));
  const LocalWindow w = graph(2).local_window(10);
  EXPECT_EQ(w.keyframes, (std::vector<int64_t>{10}));
  EXPECT_EQ(w.points, ids(0, 19));
  EXPECT_EQ(w.fixed_keyframes, (std::vector<int64_t>{2, 3}));
}

TEST(KeyframeGraph, ChainBreaksAtAMissingKeyframeAndHealsIfItArrivesLate) {
  KeyframeGraph g;
  g.insert(keyframe(0, -1, ids(0, 9)));
  g.insert(keyframe(1, 0, ids(0, 9)));
  g.insert(keyframe(2, 1, ids(0, 9)));
  g.insert(keyframe(4, 3, ids(0, 9)));  // 3 lost (so far)
  EXPECT_EQ(g.imu_predecessor(0), std::nullopt);
  EXPECT_EQ(g.imu_predecessor(1), 0);
  EXPECT_EQ(g.imu_predecessor(2), 1);
  EXPECT_EQ(g.imu_predecessor(4), std::nullopt);  // no IMU factor across the gap
  EXPECT_EQ(g.imu_successor(2), std::nullopt);
  EXPECT_EQ(g.counters().missing_prev, 1);
  EXPECT_EQ(g.counters().out_of_order, 0);

  g.insert(keyframe(3, 2, ids(0, 9)));  // late, not lost
  EXPECT_EQ(g.counters().out_of_order, 1);
  EXPECT_EQ(g.counters().missing_prev, 1);
  EXPECT_EQ(g.imu_predecessor(3), 2);
  EXPECT_EQ(g.imu_predecessor(4), 3);
  EXPECT_EQ(g.imu_successor(2), 3);
  EXPECT_EQ(g.imu_successor(3), 4);
}

TEST(KeyframeGraph, ChainRejectsImuFromAnEarlierInterval) {
  KeyframeGraph g;
  g.insert(keyframe(0, -1, ids(0, 9)));
  g.insert(keyframe(1, 0, ids(0, 9)));
  // Keyframe 2 names 1 as previous but carries the IMU from keyframe 0 on.
  hsslam::keyframe_t msg = test::keyframe_msg(2, 0, ids(0, 9));
  msg.prev_keyframe_id = 1;
  g.insert(keyframe_from_msg(msg, "KEYFRAME"));
  EXPECT_EQ(g.imu_predecessor(2), std::nullopt);
  EXPECT_EQ(g.imu_successor(1), std::nullopt);
}

TEST(KeyframeGraph, DuplicateKeyframesAreIgnoredAndCounted) {
  KeyframeGraph g;
  g.insert(keyframe(0, -1, ids(0, 9)));
  ASSERT_EQ(g.insert(keyframe(1, 0, ids(5, 14))), KeyframeGraph::InsertResult::kInserted);
  const int shared = g.shared_points(0, 1);
  EXPECT_EQ(g.insert(keyframe(1, 0, ids(5, 14))), KeyframeGraph::InsertResult::kDuplicate);
  EXPECT_EQ(g.insert(keyframe(1, 0, ids(0, 30))), KeyframeGraph::InsertResult::kDuplicate);
  EXPECT_EQ(g.counters().duplicates, 2);
  EXPECT_EQ(g.counters().inserted, 2);
  EXPECT_EQ(g.shared_points(0, 1), shared);
  EXPECT_EQ(g.num_points(), 15u);
  EXPECT_EQ(g.point(7)->observations.size(), 2u);
  // A removed keyframe replayed later stays removed.
  g.remove_keyframe(1);
  EXPECT_EQ(g.insert(keyframe(1, 0, ids(5, 14))), KeyframeGraph::InsertResult::kDuplicate);
  EXPECT_EQ(g.keyframe(1), nullptr);
}

TEST(KeyframeGraph, ANewMapStartsANewWorld) {
  KeyframeGraph g;
  g.insert(keyframe(0, -1, ids(0, 9), 0));
  g.insert(keyframe(1, 0, ids(0, 9), 0));
  g.insert(keyframe(2, -1, ids(5, 14), 1));  // the tracker started a new map: map id 1
  g.insert(keyframe(3, 2, ids(10, 19), 1));
  EXPECT_EQ(g.counters().map_changes, 1);
  EXPECT_EQ(g.counters().new_worlds, 2);
  EXPECT_NE(g.world(1), g.world(2));
  EXPECT_EQ(g.world(2), g.world(3));
  EXPECT_EQ(g.imu_predecessor(2), std::nullopt);
  EXPECT_EQ(g.imu_predecessor(3), 2);
  EXPECT_EQ(g.shared_points(1, 2), 0);
  EXPECT_EQ(g.shared_points(2, 3), 5);
  EXPECT_EQ(g.point(5)->observations.size(), 3u);  // one point, seen from both maps
  const LocalWindow w = g.local_window(2);
  EXPECT_EQ(w.keyframes, (std::vector<int64_t>{2, 3}));
  EXPECT_TRUE(w.fixed_keyframes.empty());
  EXPECT_EQ(g.local_window(0).keyframes, (std::vector<int64_t>{0, 1}));
  EXPECT_TRUE(g.local_window(0).fixed_keyframes.empty());  // keyframe 2 sees points 5..9
}

TEST(KeyframeGraph, AMapIdContinuingAKeyframeStaysInItsWorld) {
  KeyframeGraph g;
  g.insert(keyframe(0, -1, ids(0, 9), 0));
  g.insert(keyframe(1, 0, ids(0, 9), 0));
  // The tracker stated a jump of its estimate (map id 1) but kept its map: keyframe 2 follows 1.
  g.insert(keyframe(2, 1, ids(5, 14), 1));
  g.insert(keyframe(3, 2, ids(5, 14), 2));
  EXPECT_EQ(g.counters().map_changes, 2);
  EXPECT_EQ(g.counters().new_worlds, 1);
  EXPECT_EQ(g.world(3), g.world(0));
  EXPECT_EQ(g.imu_predecessor(2), 1);
  EXPECT_EQ(g.imu_predecessor(3), 2);
  EXPECT_EQ(g.shared_points(1, 2), 5);
  EXPECT_EQ(g.local_window(3).keyframes, (std::vector<int64_t>{0, 1, 2, 3}));
}

TEST(KeyframeGraph, MergedWorldsShareWindowsAndLaterMapIdsJoinThem) {
  KeyframeGraph g;
  g.insert(keyframe(0, -1, ids(0, 9), 0));
  g.insert(keyframe(1, 0, ids(0, 9), 0));
  g.insert(keyframe(2, -1, ids(20, 29), 1));  // a second world
  g.insert(keyframe(3, 2, ids(20, 29), 1));
  g.merge_world(g.world(2), g.world(0));
  EXPECT_EQ(g.world(3), g.world(0));
  g.insert(keyframe(4, 3, ids(20, 29), 2));  // a later map id of the merged world
  EXPECT_EQ(g.world(4), g.world(0));
  EXPECT_EQ(g.imu_predecessor(4), 3);
  // Found again: keyframe 3's point 20 is keyframe 0's point 0; the two worlds now share it.
  g.fuse_point(20, 0);
  EXPECT_EQ(g.point(20), nullptr);
  EXPECT_EQ(g.point(0)->observations.size(), 5u);
  EXPECT_EQ(g.shared_points(0, 3), 1);
  EXPECT_EQ(g.shared_points(3, 4), 10);  // still 10: point 0 replaced point 20 for both
  EXPECT_EQ(g.keyframe(3)->keypoints[0].point_id, 0);
  const LocalWindow w = g.local_window(3);
  EXPECT_TRUE(std::count(w.keyframes.begin(), w.keyframes.end(), 0));
}

TEST(KeyframeGraph, AFusedTrackWeighsAsDetectionsOnlyWhenAsked) {
  for (const bool as_detections : {false, true}) {
    KeyframeGraph g;
    g.insert(keyframe(0, -1, ids(0, 9)));
    g.insert(keyframe(1, 0, ids(0, 9)));
    g.insert(keyframe(2, 1, ids(20, 29)));  // the revisit: its own track of point 0, as point 20
    g.insert(keyframe(3, 2, ids(20, 29)));
    g.fuse_point(20, 0, as_detections);
    for (int64_t k : {2, 3}) {
      EXPECT_EQ(g.keyframe(k)->keypoints[0].point_id, 0);
      EXPECT_EQ(g.keyframe(k)->keypoints[0].detected, as_detections) << k;
      EXPECT_FALSE(g.keyframe(k)->keypoints[1].detected) << k;  // not fused: its own track
    }
    for (int64_t k : {0, 1}) EXPECT_FALSE(g.keyframe(k)->keypoints[0].detected) << k;
  }
}

TEST(KeyframeGraph, FusingIntoAPointAKeyframeAlreadySeesFreesTheSecondKeypoint) {
  KeyframeGraph g;
  g.insert(keyframe(0, -1, {1, 2}));
  g.insert(keyframe(1, 0, {1, 2}));
  g.fuse_point(2, 1);  // both keyframes see both: point 1 keeps one observation per keyframe
  EXPECT_EQ(g.point(1)->observations.size(), 2u);
  EXPECT_EQ(g.keyframe(0)->keypoints[1].point_id, -1);
  EXPECT_EQ(g.shared_points(0, 1), 1);
  // A free keypoint (each test keyframe's last) gains an observation; a keyframe seeing the
  // point already, or a keypoint seeing another, is refused.
  g.insert(keyframe(2, 1, {3}));
  g.add_observation(1, {2, 1});
  EXPECT_EQ(g.shared_points(1, 2), 1);
  EXPECT_EQ(g.point(1)->observations.size(), 3u);
  EXPECT_THROW(g.add_observation(1, {2, 1}), std::invalid_argument);
  EXPECT_THROW(g.add_observation(3, {0, 0}), std::invalid_argument);
}

TEST(KeyframeGraph, RemovingAKeyframeJoinsItsNeighboursImuIntervals) {
  KeyframeGraph g;
  for (int64_t i = 0; i < 4; ++i) g.insert(keyframe(i, i - 1, ids(0, 9)));
  const std::vector<ImuSample> first = g.keyframe(1)->imu, second = g.keyframe(2)->imu;
  ASSERT_TRUE(g.remove_keyframe(1));
  EXPECT_EQ(g.imu_predecessor(2), 0);
  EXPECT_EQ(g.imu_successor(0), 2);
  const std::vector<ImuSample>& merged = g.keyframe(2)->imu;
  EXPECT_EQ(merged.front().t_ns, first.front().t_ns);
  EXPECT_EQ(merged.back().t_ns, second.back().t_ns);
  for (size_t i = 1; i < merged.size(); ++i)
    EXPECT_EQ(merged[i].t_ns - merged[i - 1].t_ns, test::kImuStepNs);  // no gap, no repeat
  // The newest keyframe leaves no dangling link.
  ASSERT_TRUE(g.remove_keyframe(3));
  EXPECT_EQ(g.imu_successor(2), std::nullopt);
  EXPECT_EQ(g.counters().forks, 0);
}

TEST(KeyframeGraph, ForkedChainKeepsTheFirstLink) {
  KeyframeGraph g;
  g.insert(keyframe(0, -1, ids(0, 9)));
  g.insert(keyframe(1, 0, ids(0, 9)));
  g.insert(keyframe(2, 0, ids(0, 9)));  // also claims 0 as its predecessor
  EXPECT_EQ(g.counters().forks, 1);
  EXPECT_EQ(g.imu_predecessor(1), 0);
  EXPECT_EQ(g.imu_predecessor(2), std::nullopt);
}

TEST(KeyframeGraph, RepresentativeDescriptorIsTheMostCentralObservation) {
  auto with_descriptor = [](int64_t id, int64_t prev, uint8_t fill) {
    hsslam::keyframe_t m = test::keyframe_msg(id, prev, {7});
    std::fill(m.descriptors[0].begin(), m.descriptors[0].end(), fill);
    return keyframe_from_msg(m, "KEYFRAME");
  };
  KeyframeGraph g;
  g.insert(with_descriptor(0, -1, 0xff));  // the outlier, seen first
  g.insert(with_descriptor(1, 0, 0x00));
  g.insert(with_descriptor(2, 1, 0x01));  // 32 bits from keyframe 1's
  Descriptor expected;
  expected.fill(0x00);
  EXPECT_EQ(g.point(7)->descriptor, expected);
}

}  // namespace
}  // namespace hs
