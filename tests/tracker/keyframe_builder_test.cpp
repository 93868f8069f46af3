// Stereo matching and keyframe building on a rendered stereo pair of a textured wall at a known
// depth: matched points triangulate to the wall, and every keypoint of the keyframe keeps the
// map point id and descriptor of its own position.
#include <gtest/gtest.h>

#include <algorithm>

#include "tests/sim/render_test_util.h"
#include "tracker/keyframe_builder.h"
#include "tracker/stereo_matcher.h"

namespace hs {
namespace {

constexpr double kWallDepthM = 3.0;

class KeyframeBuilderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    sim::World world;
    sim::test::add_facing_square(&world, Eigen::Vector3d(0, 0, kWallDepthM), 6.0,
                                 {sim::TextureKind::kMixed, 7, 1.0, 1.0f});
    sim::RenderOptions render = sim::test::clean_options();
    sim::Renderer r0(world, options_.calib.cam0.intrinsics, render);
    sim::Renderer r1(r0, options_.calib.cam1.intrinsics, render);
    // World = cam0 frame, so the wall is at z = kWallDepthM in cam0.
    frame_.t_ns = 1;
    frame_.cam0 = r0.render(Eigen::Isometry3d::Identity());
    frame_.cam1 = r1.render(options_.calib.T_c0_c1());
    // cam0 from 0.25 m to the right (for the mono pair).
    T_w_c_moved_.translation() = Eigen::Vector3d(0.25, 0.0, 0.0);
    moved_cam0_ = r0.render(T_w_c_moved_);
    nav_.q_w_b = Eigen::Quaterniond(options_.calib.cam0.T_b_c.linear().transpose());
    nav_.p_w_b = -(nav_.q_w_b * options_.calib.cam0.T_b_c.translation());
  }

  TrackerOptions options_;
  StereoFrame frame_;
  Eigen::Isometry3d T_w_c_moved_ = Eigen::Isometry3d::Identity();
  cv::Mat moved_cam0_;
  NavState nav_;  // body pose that puts cam0 at the world origin
};

TEST_F(KeyframeBuilderTest, StereoMatchesTriangulateToTheWall) {
  const OrbExtractor orb(options_.orb);
  std::vector<Eigen::Vector2d> uv0;
  for (const cv::KeyPoint& kp : orb.detect(frame_.cam0)) uv0.emplace_back(kp.pt.x, kp.pt.y);
  ASSERT_GT(uv0.size(), 300u);
  const StereoMatcher matcher(options_.calib, options_.stereo_match);
  const std::vector<StereoMatch> matches = matcher.match(frame_.cam0, frame_.cam1, uv0);
  std::vector<double> rel_err;
  for (const StereoMatch& m : matches)
    if (m.valid) rel_err.push_back(std::abs(m.p_c0.z() - kWallDepthM) / kWallDepthM);
  EXPECT_GT(rel_err.size(), uv0.size() * 7 / 10);
  std::sort(rel_err.begin(), rel_err.end());
  EXPECT_LT(rel_err[rel_err.size() / 2], 0.005);        // median depth error < 0.5%
  EXPECT_LT(rel_err[rel_err.size() * 95 / 100], 0.03);  // 95% within 3%
}

TEST_F(KeyframeBuilderTest, KeypointsKeepTheirPointIdsAndDescriptors) {
  LocalMap map(options_.local_map);
  // Tracked points: a grid of positions (most not on a detected corner, so they become
  // keypoints of their own), and one too close to the border for a descriptor.
  std::vector<TrackedObservation> tracked;
  std::vector<Eigen::Vector2d> where;
  for (double v = 60; v < 440; v += 95)
    for (double u = 50; u < 720; u += 83) where.emplace_back(u + 0.37, v + 0.61);
  where.emplace_back(2.0, 240.0);
  for (const Eigen::Vector2d& uv : where) {
    MapPoint p;
    p.id = map.new_point_id();
    p.p_w = options_.calib.cam0.intrinsics.unproject(uv) * kWallDepthM;
    map.add_point(p);
    tracked.push_back({p.id, uv});
  }
  const ImagePyramid pyr = build_pyramid(frame_.cam0, options_.pyramid_levels);
  KeyframeBuilder builder(options_);
  KeyframeBuildStats stats;
  const auto kf = builder.build(frame_, pyr, nav_, tracked, nullptr, map, &stats);

  const size_t n = kf->features.size();
  ASSERT_EQ(kf->point_ids.size(), n);
  ASSERT_EQ(static_cast<size_t>(kf->features.descriptors.rows), n);
  ASSERT_EQ(kf->depth.size(), n);
  EXPECT_EQ(stats.attached, static_cast<int>(tracked.size()) - 1);  // all but the border one
  EXPECT_GT(stats.new_points, 50);

  // Each tracked id sits on a keypoint at its own pixel (attached within 2 px).
  for (size_t k = 0; k < tracked.size(); ++k) {
    const auto it = std::find(kf->point_ids.begin(), kf->point_ids.end(), tracked[k].point_id);
    if (k + 1 == tracked.size()) {
      EXPECT_EQ(it, kf->point_ids.end()) << "the border point cannot have a descriptor";
      continue;
    }
    ASSERT_NE(it, kf->point_ids.end()) << "tracked point " << k << " lost";
    const cv::KeyPoint& kp = kf->features.keypoints[it - kf->point_ids.begin()];
    EXPECT_LT((Eigen::Vector2d(kp.pt.x, kp.pt.y) - tracked[k].uv).norm(), 2.0) << k;
  }
  // New points lie on the wall and their descriptor row is the one computed at their keypoint.
  const OrbExtractor& orb = builder.orb();
  int checked = 0;
  for (size_t i = 0; i < n && checked < 20; ++i) {
    if (kf->depth[i] <= 0) continue;
    const MapPoint* p = map.point(kf->point_ids[i]);
    ASSERT_NE(p, nullptr);
    EXPECT_NEAR(p->p_w.z(), kWallDepthM, 0.1);
    const OrbFeatures again = orb.describe(frame_.cam0, {kf->features.keypoints[i]});
    ASSERT_EQ(again.size(), 1u);
    EXPECT_EQ(cv::norm(again.descriptors, kf->features.descriptors.row(static_cast<int>(i)),
                       cv::NORM_HAMMING),
              0.0);
    ++checked;
  }
  EXPECT_EQ(checked, 20);
}

// A tracked point's patch (its reference keyframe) moves to every new keyframe, or, with
// reanchor_every_keyframe off, stays on the keyframe that made it until that keyframe is about
// to leave the window (its image goes with it).
TEST_F(KeyframeBuilderTest, PointsReanchorEveryKeyframeOrWhenTheirReferenceLeavesTheWindow) {
  for (const bool every : {true, false}) {
    SCOPED_TRACE(every ? "every keyframe" : "when leaving");
    TrackerOptions options = options_;
    options.reanchor_every_keyframe = every;
    options.local_map.max_keyframes = 2;
    LocalMap map(options.local_map);
    const ImagePyramid pyr = build_pyramid(frame_.cam0, options.pyramid_levels);
    KeyframeBuilder builder(options);
    KeyframeBuildStats stats;
    const auto first = builder.build(frame_, pyr, nav_, {}, nullptr, map, &stats);
    map.add_keyframe(first);
    std::vector<TrackedObservation> tracked;  // the first keyframe's points, seen again
    for (size_t i = 0; i < first->point_ids.size() && tracked.size() < 40; ++i)
      if (first->point_ids[i] >= 0) tracked.push_back({first->point_ids[i], first->features.uv(i)});
    ASSERT_EQ(tracked.size(), 40u);
    const auto refs = [&] {
      std::vector<int64_t> out;
      for (const TrackedObservation& t : tracked)
        out.push_back(map.point(t.point_id)->ref_keyframe_id);
      return out;
    };

    const auto second = builder.build(frame_, pyr, nav_, tracked, nullptr, map, &stats);
    EXPECT_EQ(refs(), std::vector<int64_t>(tracked.size(), every ? second->id : first->id));
    map.add_keyframe(second);
    // The window is full: the first keyframe leaves it when the third is added.
    const auto third = builder.build(frame_, pyr, nav_, tracked, nullptr, map, &stats);
    EXPECT_EQ(refs(), std::vector<int64_t>(tracked.size(), third->id));
  }
}

// Mono rig: a keyframe's new points come from epipolar matches with the previous keyframe,
// triangulated onto the wall; its tracked points and the first keyframe's keypoints make none.
TEST_F(KeyframeBuilderTest, MonoKeyframesTriangulateWithThePreviousKeyframe) {
  options_.stereo = false;
  KeyframeBuilder builder(options_);
  LocalMap map(options_.local_map);
  StereoFrame first{frame_.t_ns, frame_.seq, frame_.cam0, cv::Mat()};
  KeyframeBuildStats stats;
  map.add_keyframe(builder.build(first, build_pyramid(first.cam0, options_.pyramid_levels), nav_,
                                 {}, nullptr, map, &stats));
  EXPECT_EQ(stats.new_points, 0) << "nothing to match the first keyframe with";

  StereoFrame second{2, 1, moved_cam0_, cv::Mat()};
  NavState nav = nav_;
  const Eigen::Isometry3d T_w_b = T_w_c_moved_ * options_.calib.cam0.T_b_c.inverse();
  nav.p_w_b = T_w_b.translation();
  const auto kf = builder.build(second, build_pyramid(second.cam0, options_.pyramid_levels), nav,
                                {}, nullptr, map, &stats);
  EXPECT_GT(stats.new_points, 60);
  EXPECT_EQ(stats.stereo_matched, 0);
  int on_wall = 0;
  for (size_t i = 0; i < kf->point_ids.size(); ++i) {
    if (kf->point_ids[i] < 0) continue;
    EXPECT_LT(kf->depth[i], 0.f) << "a mono point has no stereo depth to report";
    const MapPoint* p = map.point(kf->point_ids[i]);
    ASSERT_NE(p, nullptr);
    EXPECT_EQ(p->ref_keyframe_id, kf->id);
    // 0.25 m at 3 m: a pixel of keypoint error is 2.6% of the depth.
    on_wall += std::abs(p->p_w.z() - kWallDepthM) < 0.05 * kWallDepthM;
  }
  // A few wrong matches on the repeated texture remain (the pose optimisation rejects them).
  EXPECT_GE(on_wall, stats.new_points * 90 / 100);
}

}  // namespace
}  // namespace hs
