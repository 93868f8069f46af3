// hs-viewer --headless beside the real hs-tracker, fed by stock lcm-logplayer over udpm on
// loopback: it writes views (PNG frames, a video, a snapshot) that show the image with the
// tracker's features and the trajectory.
#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "tests/common/child_process.h"
#include "tests/common/process_test_util.h"
#include "tests/common/sim_log_util.h"
#include "tests/dataset/dataset_test_util.h"
#include "tools/viewer/viewer_render.h"

namespace hs {
namespace {

namespace fs = std::filesystem;
using test::ChildProcess;
using test::wait_for;

bool says(ChildProcess& p, const std::string& word) {
  return wait_for([&] { return p.output().find(word) != std::string::npos; }, 20);
}

// Pixels of a colour (within 10 per channel) inside `area`.
int count_colour(const cv::Mat& view, const cv::Rect& area, const cv::Scalar& colour) {
  int n = 0;
  const cv::Mat roi = view(area);
  for (int y = 0; y < roi.rows; ++y)
    for (int x = 0; x < roi.cols; ++x) {
      const cv::Vec3b c = roi.at<cv::Vec3b>(y, x);
      n += std::abs(c[0] - colour[0]) < 10 && std::abs(c[1] - colour[1]) < 10 &&
           std::abs(c[2] - colour[2]) < 10;
    }
  return n;
}

TEST(ViewerProcess, HeadlessViewsOfAReplayShowFeaturesAndTrajectory) {
  test::TempDir dir;
  const std::string d = dir.path();
  const std::string url = test::private_udpm_url(31);
  ASSERT_TRUE(test::make_sim_log(HS_SIM, HS_EUROC2LCM, d, 5));

  ChildProcess tracker({HS_TRACKER, "--calib", d + "/sim", "--lcm-url", url}, d + "/tracker.txt");
  ChildProcess viewer(
      {HS_VIEWER, "--headless", "--out", d + "/views", "--video", d + "/view.avi", "--snapshot",
       d + "/last.png", "--fps", "4", "--idle-exit", "2", "--lcm-url", url},
      d + "/viewer.txt");
  ASSERT_TRUE(says(tracker, "listening")) << tracker.output();
  ASSERT_TRUE(says(viewer, "listening")) << viewer.output();
  ChildProcess player({"lcm-logplayer", "-l", url, d + "/sim.lcmlog"}, d + "/player.txt");
  ASSERT_TRUE(wait_for([&] { return !viewer.running(); }, 30)) << viewer.output();
  EXPECT_EQ(viewer.wait(), 0) << viewer.output();
  EXPECT_EQ(player.wait(), 0);
  tracker.signal(SIGINT);
  EXPECT_EQ(tracker.wait(), 0) << tracker.output();
  EXPECT_NE(viewer.output().find("0 bad messages"), std::string::npos) << viewer.output();

  // About fps x the replay's length in views, and a video.
  int views = 0;
  for (const auto& e : fs::directory_iterator(d + "/views"))
    views += e.path().extension() == ".png";
  EXPECT_GE(views, 10) << viewer.output();
  EXPECT_GT(fs::file_size(d + "/view.avi"), 10'000u);

  // The last view: the image panel carries direct features (green dots), the top view a path.
  const cv::Mat last = cv::imread(d + "/last.png");
  const ViewerLayout layout;
  ASSERT_EQ(last.size(), layout.canvas);
  EXPECT_GT(count_colour(last, layout.image, kDirectColour), 200) << "no direct features drawn";
  EXPECT_GT(count_colour(last, layout.top_view, cv::Scalar(255, 200, 80)), 20) << "no path";
}

}  // namespace
}  // namespace hs
