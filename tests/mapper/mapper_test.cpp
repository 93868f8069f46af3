#include "mapper/mapper.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "common/lcm/convert.h"
#include "tests/mapper/keyframe_test_util.h"

namespace hs {
namespace {

using test::ids;

// Point id k on a 10 x 10 grid in front of the first keyframe's camera, 4-6 m deep.
Eigen::Vector3d point_w(int64_t k) {
  const StereoCalib calib = euroc_stereo_calib();
  NavState first;  // keyframe 0 of test::keyframe_msg: at the origin, level
  const Eigen::Vector3d p_c(-1.0 + 0.2 * static_cast<double>(k % 10),
                            -0.8 + 0.16 * static_cast<double>(k / 10 % 10),
                            4.0 + 0.02 * static_cast<double>(k % 100));
  return first.T_w_b() * calib.cam0.T_b_c * p_c;
}

// test::keyframe_msg with its keypoints where the points project (cam0, and cam1 for the right
// pixel). The keypoint of point `bad_point` (if >= 0) is put 40 px off, left or right by keyframe.
MapperKeyframe consistent_keyframe(int64_t id, int64_t prev_id, const std::vector<int64_t>& points,
                                   int32_t map_id = 0, int64_t bad_point = -1) {
  const StereoCalib calib = euroc_stereo_calib();
  hsslam::keyframe_t m = test::keyframe_msg(id, prev_id, points, map_id);
  const NavState x = keyframe_pose_from_msg(m.pose, "test");
  const Eigen::Isometry3d T_c0_w = (x.T_w_b() * calib.cam0.T_b_c).inverse();
  const Eigen::Isometry3d T_c1_w = (x.T_w_b() * calib.cam1.T_b_c).inverse();
  for (hsslam::keypoint_t& k : m.keypoints) {
    if (k.map_point_id < 0) continue;
    const Eigen::Vector3d p_w = point_w(k.map_point_id);
    const Eigen::Vector2d uv = calib.cam0.intrinsics.project(T_c0_w * p_w);
    k.u = static_cast<float>(uv.x());
    k.v = static_cast<float>(uv.y());
    const Eigen::Vector2d uv_right = calib.cam1.intrinsics.project(T_c1_w * p_w);
    k.u_right = static_cast<float>(uv_right.x());
    k.v_right = static_cast<float>(uv_right.y());
    k.depth = static_cast<float>((T_c0_w * p_w).z());
    if (k.map_point_id == bad_point) {
      const float off = id % 2 ? 40.f : -40.f;
      k.u += off, k.u_right += off;
    }
  }
  for (hsslam::map_point_t& p : m.points) {
    const Eigen::Vector3d p_w = point_w(p.id);
    for (int i = 0; i < 3; ++i) p.p_w[i] = p_w[i];
  }
  return keyframe_from_msg(m, "KEYFRAME");
}

TEST(Mapper, EachKeyframeGivesACorrectionOfItsWindow) {
  Mapper mapper(euroc_stereo_calib(), MapperOptions{});
  const MapperStep first = mapper.add_keyframe(consistent_keyframe(0, -1, ids(0, 9)));
  ASSERT_TRUE(first.correction);
  EXPECT_EQ(first.correction->seq, 0);
  const MapperStep second = mapper.add_keyframe(consistent_keyframe(1, 0, ids(5, 14)));
  ASSERT_TRUE(second.correction);
  const MapCorrection& c = *second.correction;
  EXPECT_EQ(c.seq, 1);
  EXPECT_EQ(c.map_id, 0);
  EXPECT_EQ(c.t_ns, test::keyframe_time(1));
  // Both keyframes share points: both are in the window, with the 5 points both see (those
  // one keyframe sees constrain no pose: left out), none an outlier.
  ASSERT_EQ(c.keyframes.size(), 2u);
  ASSERT_EQ(c.points.size(), 5u);
  EXPECT_EQ(c.points.front().id, 5);
  EXPECT_EQ(c.points.back().id, 9);
  EXPECT_TRUE(c.removed_points.empty());
  EXPECT_EQ(second.ba.num_outliers, 0);
  EXPECT_EQ(second.window_keyframes, 2);
  EXPECT_GT(second.ba.rounds, 0);
  EXPECT_EQ(mapper.counters().local_ba_runs, 2);
}

// consistent_keyframe plus free keypoints (no tracker point) where points `free` project, each
// with its point's descriptor.
MapperKeyframe with_free_keypoints(MapperKeyframe kf, const std::vector<int64_t>& free) {
  const StereoCalib calib = euroc_stereo_calib();
  const Eigen::Isometry3d T_c0_w = (kf.state.T_w_b() * calib.cam0.T_b_c).inverse();
  for (int64_t k : free) {
    Eigen::Vector2d uv;
    if (!calib.cam0.intrinsics.project(T_c0_w * point_w(k), &uv)) continue;
    MapperKeypoint kp;
    kp.u = static_cast<float>(uv.x());
    kp.v = static_cast<float>(uv.y());
    kf.keypoints.push_back(kp);
    const std::vector<uint8_t> d = test::point_descriptor(k);
    std::copy(d.begin(), d.end(), kf.descriptors.emplace_back().begin());
  }
  return kf;
}

TEST(Mapper, ItsOwnPointsJoinTheBundleAdjustmentButNotTheCorrection) {
  MapperOptions options;
  options.new_points.covisible_keyframes = 10;
  Mapper mapper(euroc_stereo_calib(), options);
  const std::vector<int64_t> free = ids(40, 59);
  mapper.add_keyframe(with_free_keypoints(consistent_keyframe(0, -1, ids(0, 9)), free));
  // 0.5 m on (keyframe ids are 0.1 m apart): parallax for the free points 4-6 m away.
  const MapperStep step =
      mapper.add_keyframe(with_free_keypoints(consistent_keyframe(5, 0, ids(0, 9)), free));
  EXPECT_EQ(step.new_points, static_cast<int>(free.size()));
  EXPECT_EQ(mapper.counters().new_points, static_cast<int64_t>(free.size()));
  EXPECT_EQ(step.window_points, 10 + static_cast<int>(free.size()));
  EXPECT_EQ(step.ba.num_outliers, 0);
  ASSERT_TRUE(step.correction);
  // The tracker hears only of its own points.
  ASSERT_EQ(step.correction->points.size(), 10u);
  for (const PointCorrection& p : step.correction->points) EXPECT_FALSE(mapper_made_point(p.id));
  EXPECT_EQ(mapper.graph().shared_points(0, 5), 10 + static_cast<int>(free.size()));
}

TEST(Mapper, PointFailingTheBundleAdjustmentIsRemovedAndListed) {
  Mapper mapper(euroc_stereo_calib(), MapperOptions{});
  std::vector<int64_t> removed;
  // Point 7 is right where keyframe 0 created it, then mistracked 40 px off in every keyframe.
  for (int64_t id = 0; id < 4; ++id) {
    const MapperStep step =
        mapper.add_keyframe(consistent_keyframe(id, id - 1, ids(0, 29), 0, id == 0 ? -1 : 7));
    ASSERT_TRUE(step.correction);
    removed.insert(removed.end(), step.correction->removed_points.begin(),
                   step.correction->removed_points.end());
  }
  EXPECT_EQ(removed, std::vector<int64_t>{7});
  EXPECT_EQ(mapper.graph().point(7), nullptr);
  EXPECT_EQ(mapper.counters().removed_points, 1);
  // The later keyframes still named it (the tracker here never applies the removal).
  EXPECT_GT(mapper.counters().removed_point_observations, 0);
}

TEST(Mapper, DuplicateKeyframeIsIgnoredWithAMessage) {
  Mapper mapper(euroc_stereo_calib(), MapperOptions{});
  ASSERT_TRUE(mapper.add_keyframe(consistent_keyframe(0, -1, ids(0, 9))).correction);
  const MapperStep dup = mapper.add_keyframe(consistent_keyframe(0, -1, ids(0, 9)));
  EXPECT_FALSE(dup.correction);
  EXPECT_NE(dup.message.find("keyframe 0 seen before"), std::string::npos) << dup.message;
  EXPECT_EQ(mapper.counters().keyframes, 1);
  EXPECT_EQ(mapper.graph().counters().duplicates, 1);
}

TEST(Mapper, CorrectionsStayInTheKeyframesWorld) {
  Mapper mapper(euroc_stereo_calib(), MapperOptions{});
  mapper.add_keyframe(consistent_keyframe(0, -1, ids(0, 9), 0));
  const MapperStep other = mapper.add_keyframe(consistent_keyframe(1, -1, ids(5, 14), 1));
  ASSERT_TRUE(other.correction);
  EXPECT_EQ(other.correction->map_id, 1);
  // A new map: the points are shared, the worlds are not. Keyframe 0 is neither optimised nor
  // sent.
  ASSERT_EQ(other.correction->keyframes.size(), 1u);
  EXPECT_EQ(other.correction->keyframes[0].id, 1);
}

TEST(Mapper, AStatedJumpKeepsTheWorld) {
  Mapper mapper(euroc_stereo_calib(), MapperOptions{});
  mapper.add_keyframe(consistent_keyframe(0, -1, ids(0, 9), 0));
  // Map id 1 continues keyframe 0: the tracker stated a jump but kept its map.
  const MapperStep next = mapper.add_keyframe(consistent_keyframe(1, 0, ids(5, 14), 1));
  ASSERT_TRUE(next.correction);
  EXPECT_EQ(next.correction->map_id, 1);
  EXPECT_EQ(next.window_keyframes, 2);
}

}  // namespace
}  // namespace hs
