#include "tools/viewer/viewer_render.h"

#include <gtest/gtest.h>

namespace hs {
namespace {

cv::Vec3b bgr(const cv::Scalar& s) {
  return cv::Vec3b(static_cast<uint8_t>(s[0]), static_cast<uint8_t>(s[1]),
                   static_cast<uint8_t>(s[2]));
}

TEST(ViewerRender, FeaturesAreDrawnWhereTheyAreInTheColourOfHowTheyWereFound) {
  ViewerModel m;
  m.on_image(10, cv::Mat(480, 752, CV_8UC1, cv::Scalar(100)));
  hsslam::tracker_status_t s{};
  s.t_ns = 10;
  s.state = hsslam::odometry_t::TRACKING;
  s.feature_u = {100, 300, 600};
  s.feature_v = {100, 200, 400};
  s.feature_source = {hsslam::tracker_status_t::FEATURE_DIRECT,
                      hsslam::tracker_status_t::FEATURE_DESCRIPTOR,
                      hsslam::tracker_status_t::FEATURE_NEW};
  s.num_features = 3;
  m.on_status(s);
  const ViewerLayout layout;
  const cv::Mat view = render_view(m, layout);
  ASSERT_EQ(view.size(), layout.canvas);
  const cv::Scalar colours[] = {kDirectColour, kDescriptorColour, kNewColour};
  for (int i = 0; i < 3; ++i) {
    const cv::Point2f at = layout.image_to_canvas({752, 480}, {s.feature_u[i], s.feature_v[i]});
    EXPECT_EQ(view.at<cv::Vec3b>(cvRound(at.y), cvRound(at.x)), bgr(colours[i])) << i;
  }
  // Elsewhere the image itself (gray 100), scaled into its panel.
  const cv::Point2f plain = layout.image_to_canvas({752, 480}, {400, 50});
  EXPECT_EQ(view.at<cv::Vec3b>(cvRound(plain.y), cvRound(plain.x)), cv::Vec3b(100, 100, 100));
}

TEST(ViewerRender, ImageToCanvasKeepsTheAspectInsideThePanel) {
  const ViewerLayout layout;
  const cv::Point2f tl = layout.image_to_canvas({752, 480}, {0, 0});
  const cv::Point2f br = layout.image_to_canvas({752, 480}, {752, 480});
  EXPECT_TRUE(layout.image.contains(cv::Point(cvRound(tl.x), cvRound(tl.y))));
  EXPECT_LE(br.x, layout.image.x + layout.image.width + 0.01f);
  EXPECT_LE(br.y, layout.image.y + layout.image.height + 0.01f);
  EXPECT_NEAR((br.x - tl.x) / (br.y - tl.y), 752.0 / 480.0, 1e-3);
}

TEST(ViewerRender, TheTopViewShowsTheTrajectoryAndTheCurrentHeading) {
  ViewerModel m;
  for (int i = 0; i <= 50; ++i) {
    hsslam::odometry_t p{};
    p.t_ns = i;
    p.state = hsslam::odometry_t::TRACKING;
    p.p_w_b[0] = 0.1 * i;  // 5 m along x
    p.q_w_b[0] = 1;
    m.on_pose(p);
  }
  hsslam::keyframe_t kf{};
  kf.pose.id = 1;
  kf.points = {{1, {1000, 1000, 0}}};  // far outside the view: clipped, no crash
  kf.num_points = 1;
  m.on_keyframe(kf);
  const ViewerLayout layout;
  const cv::Mat view = render_view(m, layout);
  const cv::Mat top = view(layout.top_view);
  // The path is drawn across the middle of the panel, from one side towards the other.
  int path_columns = 0;
  for (int x = 0; x < top.cols; ++x) {
    bool any = false;
    for (int y = top.rows / 2 - 3; y <= top.rows / 2 + 3; ++y) {
      const cv::Vec3b c = top.at<cv::Vec3b>(y, x);
      any |= c[0] > 200 && c[1] > 150;  // map 0's colour
    }
    path_columns += any;
  }
  EXPECT_GT(path_columns, top.cols / 2);
  // The heading arrow (red) at the end.
  int red = 0;
  for (int y = 0; y < top.rows; ++y)
    for (int x = 0; x < top.cols; ++x) {
      const cv::Vec3b c = top.at<cv::Vec3b>(y, x);
      red += c[2] > 200 && c[0] < 120 && c[1] < 120;
    }
  EXPECT_GT(red, 10);
}

TEST(ViewerRender, AnEmptyModelRendersAWaitingView) {
  const cv::Mat view = render_view(ViewerModel{});
  EXPECT_EQ(view.size(), ViewerLayout{}.canvas);
  EXPECT_EQ(view.type(), CV_8UC3);
}

}  // namespace
}  // namespace hs
