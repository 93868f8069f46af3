#include "tools/viewer/viewer_model.h"

#include <gtest/gtest.h>

namespace hs {
namespace {

cv::Mat image_of(uint8_t value) {
  return cv::Mat(48, 64, CV_8UC1, cv::Scalar(value));
}

hsslam::tracker_status_t status_at(int64_t t_ns, float total_ms = 2, bool keyframe = false) {
  hsslam::tracker_status_t s{};
  s.t_ns = t_ns;
  s.is_keyframe = keyframe;
  s.total_ms = total_ms;
  s.stage_names = {"direct_align", "pose_opt"};
  s.stage_ms = {total_ms * 0.75f, total_ms * 0.25f};
  s.num_stages = 2;
  return s;
}

TEST(ViewerModel, AStatusIsShownWithItsOwnImageWhicheverComesFirst) {
  ViewerModel m;
  m.on_image(100, image_of(1));
  m.on_image(200, image_of(2));
  m.on_image(300, image_of(3));
  EXPECT_FALSE(m.frame().has_value());
  m.on_status(status_at(200));  // the tracker is a frame behind the camera
  ASSERT_TRUE(m.frame());
  EXPECT_EQ(m.frame()->image.at<uint8_t>(0, 0), 2);
  EXPECT_EQ(m.frame()->status.t_ns, 200);
  // A status heard before its image (another host): shown once the image comes.
  m.on_status(status_at(400));
  EXPECT_EQ(m.frame()->status.t_ns, 200);
  m.on_image(400, image_of(4));
  EXPECT_EQ(m.frame()->status.t_ns, 400);
  EXPECT_EQ(m.frame()->image.at<uint8_t>(0, 0), 4);
  EXPECT_EQ(m.first_t_ns(), 200);
}

TEST(ViewerModel, ImageHistoryIsBounded) {
  ViewerModel m(/*image_history=*/2);
  for (int i = 1; i <= 5; ++i) m.on_image(i * 100, image_of(static_cast<uint8_t>(i)));
  m.on_status(status_at(200));  // its image is gone
  EXPECT_FALSE(m.frame().has_value());
  m.on_status(status_at(400));
  ASSERT_TRUE(m.frame());
  EXPECT_EQ(m.frame()->image.at<uint8_t>(0, 0), 4);
}

TEST(ViewerModel, MapUpdatesMoveKeyframesAndPointsAndRemovePoints) {
  ViewerModel m;
  hsslam::keyframe_t kf{};
  kf.map_id = 0;
  kf.pose.id = 7;
  kf.pose.p_w_b[0] = 1.0;
  kf.points = {{11, {1, 2, 3}}, {12, {4, 5, 6}}, {13, {7, 8, 9}}};
  kf.num_points = 3;
  m.on_keyframe(kf);
  ASSERT_EQ(m.keyframes().size(), 1u);
  EXPECT_FALSE(m.keyframes().at(7).corrected);
  EXPECT_EQ(m.points().size(), 3u);

  hsslam::map_update_t u{};
  hsslam::keyframe_pose_t moved{};
  moved.id = 7;
  moved.p_w_b[0] = 1.5;
  hsslam::keyframe_pose_t unknown{};
  unknown.id = 99;  // a keyframe the viewer never heard: ignored
  u.keyframes = {moved, unknown};
  u.num_keyframes = 2;
  u.points = {{12, {4.5, 5, 6}}, {77, {0, 0, 0}}};
  u.num_points = 2;
  u.removed_point_ids = {13};
  u.num_removed_points = 1;
  m.on_map_update(u);
  EXPECT_EQ(m.keyframes().size(), 1u);
  EXPECT_TRUE(m.keyframes().at(7).corrected);
  EXPECT_DOUBLE_EQ(m.keyframes().at(7).p_w.x(), 1.5);
  EXPECT_EQ(m.points().size(), 2u);  // 13 removed, 77 never seen: not added
  EXPECT_DOUBLE_EQ(m.points().at(12).x(), 4.5);
  EXPECT_EQ(m.map_updates(), 1);
}

TEST(ViewerModel, PosesBecomeTheTrajectoryWithHeading) {
  ViewerModel m;
  hsslam::odometry_t p{};
  p.t_ns = 5;
  p.map_id = 2;
  p.state = hsslam::odometry_t::TRACKING;
  p.p_w_b[1] = 3.0;
  const double half = 0.5 * M_PI / 2;  // 90 deg about z: body x along world y
  p.q_w_b[0] = std::cos(half);
  p.q_w_b[3] = std::sin(half);
  m.on_pose(p);
  ASSERT_EQ(m.trajectory().size(), 1u);
  EXPECT_EQ(m.trajectory()[0].map_id, 2);
  EXPECT_DOUBLE_EQ(m.trajectory()[0].p_w.y(), 3.0);
  EXPECT_NEAR(m.trajectory()[0].yaw, M_PI / 2, 1e-12);
}

TEST(ViewerModel, TimingSeparatesKeyframesAndKeepsTheStageOrder) {
  ViewerModel m(40, /*timing_window=*/4);
  m.on_status(status_at(1, 100));  // falls out of the window
  m.on_status(status_at(2, 2));
  m.on_status(status_at(3, 4));
  m.on_status(status_at(4, 12, true));
  m.on_status(status_at(5, 0));  // not tracked: not counted
  const TimingSummary t = m.timing();
  EXPECT_EQ(t.frames, 3);
  EXPECT_EQ(t.keyframes, 1);
  EXPECT_DOUBLE_EQ(t.mean_ms, 6.0);
  EXPECT_DOUBLE_EQ(t.mean_other_ms, 3.0);
  EXPECT_DOUBLE_EQ(t.mean_keyframe_ms, 12.0);
  EXPECT_DOUBLE_EQ(t.max_ms, 12.0);
  ASSERT_EQ(t.mean_stage_ms.size(), 2u);
  EXPECT_EQ(t.mean_stage_ms[0].first, "direct_align");
  EXPECT_DOUBLE_EQ(t.mean_stage_ms[0].second, 4.5);
}

TEST(ViewerModel, EveryChangeBumpsTheVersionAndBadMessagesAreCounted) {
  ViewerModel m;
  const uint64_t v0 = m.version();
  m.on_bad_message("POSE: truncated");
  EXPECT_GT(m.version(), v0);
  EXPECT_EQ(m.bad_messages(), 1);
  EXPECT_EQ(m.last_bad_message(), "POSE: truncated");
}

}  // namespace
}  // namespace hs
