// hs-viewer --headless beside the real hs-tracker, fed by stock lcm-logplayer over udpm on
// loopback: it writes views (PNG frames, a video, a snapshot) that show the image with the
// tracker's features and the trajectory.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "hsslam/odometry_t.hpp"

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

// With a display (a real X server, Xvfb): the window opens at the view's size, shows what comes
// in, and the viewer quits on `q` typed into it.
TEST(ViewerProcess, OpensAWindowOnADisplayAndQuitsOnQ) {
  if (::system("command -v Xvfb >/dev/null && command -v xwininfo >/dev/null && "
               "command -v xdotool >/dev/null") != 0)
    GTEST_SKIP() << "Xvfb, xwininfo or xdotool missing (packages xvfb x11-utils xdotool): the "
                    "window is not tested";
  test::TempDir dir;
  const std::string d = dir.path();
  const std::string display = ":" + std::to_string(50 + ::getpid() % 200);
  ChildProcess xvfb({"Xvfb", display, "-screen", "0", "1400x900x24", "-nolisten", "tcp"},
                    d + "/xvfb.txt");
  ASSERT_TRUE(wait_for([&] { return fs::exists("/tmp/.X11-unix/X" + display.substr(1)); }, 10))
      << xvfb.output();
  const std::string url = test::private_udpm_url(37);
  // `env` execs the viewer: the pid is the viewer's.
  ChildProcess viewer(
      {"env", "DISPLAY=" + display, HS_VIEWER, "--snapshot", d + "/last.png", "--lcm-url", url},
      d + "/viewer.txt");
  ASSERT_TRUE(says(viewer, "listening")) << viewer.output();
  lcm::LCM lcm(url);
  for (int i = 0; i < 20; ++i) {
    hsslam::odometry_t p{};
    p.t_ns = i * 50'000'000;
    p.seq = i;
    p.state = hsslam::odometry_t::TRACKING;
    p.p_w_b[0] = 0.05 * i;
    p.q_w_b[0] = 1;
    lcm.publish("POSE", &p);
  }
  std::this_thread::sleep_for(std::chrono::seconds(1));  // received and drawn
  const std::string info = "xwininfo -display " + display + " -name HS-SLAM";
  ASSERT_TRUE(wait_for([&] { return ::system((info + " >/dev/null 2>&1").c_str()) == 0; }, 10))
      << viewer.output();
  ChildProcess size({"sh", "-c", info + " | grep -E 'Width|Height'"}, d + "/size.txt");
  size.wait();
  EXPECT_NE(size.output().find("Width: 1280"), std::string::npos) << size.output();
  EXPECT_NE(size.output().find("Height: 720"), std::string::npos) << size.output();
  ChildProcess key({"env", "DISPLAY=" + display, "xdotool", "search", "--name", "HS-SLAM",
                    "windowfocus", "--sync", "key", "q"},
                   d + "/key.txt");
  key.wait();
  ASSERT_TRUE(wait_for([&] { return !viewer.running(); }, 10)) << viewer.output() << key.output();
  EXPECT_EQ(viewer.wait(), 0) << viewer.output();
  EXPECT_NE(viewer.output().find("20 poses"), std::string::npos) << viewer.output();
  EXPECT_TRUE(fs::exists(d + "/last.png"));
}

}  // namespace
}  // namespace hs
