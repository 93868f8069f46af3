// hs-logger as a process over udpm on loopback: what it records after a kill -9 (all but the
// last flush period), after a simulated power cut (a truncated file: the torn event is found
// and skipped), that stock lcm-logplayer replays its files, and that a stop loses nothing that
// had arrived.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>
#include <thread>

#include "hsslam/odometry_t.hpp"
#include "logger/lcm_log_format.h"
#include "tests/common/child_process.h"
#include "tests/common/process_test_util.h"
#include "tests/dataset/dataset_test_util.h"

namespace hs {
namespace {

namespace fs = std::filesystem;
using Child = test::ChildProcess;

constexpr int kPoses = 150;
constexpr int kLostFrom = 60, kLostTo = 64;  // seq never sent: lost upstream

int count_channel(const std::vector<LogEvent>& events, const std::string& channel) {
  int n = 0;
  for (const LogEvent& e : events) n += e.channel == channel;
  return n;
}

class LoggerProcess : public ::testing::Test {
 protected:
  void SetUp() override {
    config_ = dir_ + "/logger.yaml";
    std::ofstream(config_) << "logger:\n  exclude: [\"IGNORED.*\"]\n";
  }

  // Starts hs-logger recording into dir_/logs and waits until it has subscribed.
  std::unique_ptr<Child> start_logger() {
    auto logger = std::make_unique<Child>(
        std::vector<std::string>{HS_BINARY_DIR "/bin/hs-logger", "--config", config_, "--dir",
                                 dir_ + "/logs", "--lcm-url", url_},
        dir_ + "/logger.txt");
    EXPECT_TRUE(logger->started());
    EXPECT_TRUE(
        test::wait_for([&] { return logger->output().find("recording") != std::string::npos; }, 10))
        << logger->output();
    return logger;
  }

  // Publishes POSE seq 0..kPoses-1 (without kLostFrom..kLostTo) and IGNORED, 5 ms apart.
  void publish() {
    lcm::LCM pub(url_);
    ASSERT_TRUE(pub.good());
    for (int seq = 0; seq < kPoses; ++seq) {
      if (seq >= kLostFrom && seq <= kLostTo) continue;
      hsslam::odometry_t m{};
      m.t_ns = 1'000'000 * seq;
      m.seq = seq;
      pub.publish("POSE", &m);
      pub.publish("IGNORED_DEBUG", &m);
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }

  std::vector<std::string> log_files() const {
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(dir_ + "/logs"))
      if (e.path().extension() == ".lcmlog") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    return files;
  }

  test::TempDir tmp_;
  std::string dir_ = tmp_.path(), config_;
  std::string url_ = test::private_udpm_url(17);
};

TEST_F(LoggerProcess, KillNineKeepsAllButTheLastFlushAndAPowerCutLosesOneEvent) {
  auto logger = start_logger();
  publish();
  // Past the 50 ms flush period: everything sent is on disk now.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  logger->signal(SIGKILL);
  logger->wait();
  const std::vector<std::string> files = log_files();
  ASSERT_EQ(files.size(), 1u);
  EXPECT_FALSE(fs::exists(files[0] + ".manifest.json"));  // killed before closing it
  const LogScan scan = scan_log_file(files[0]);
  const int sent = kPoses - (kLostTo - kLostFrom + 1);
  EXPECT_EQ(count_channel(scan.events, "POSE"), sent);
  EXPECT_EQ(count_channel(scan.events, "IGNORED_DEBUG"), 0);
  EXPECT_EQ(scan.torn_tail_bytes, 0);

  // A power cut in the middle of the last write.
  fs::resize_file(files[0], fs::file_size(files[0]) - 30);
  const LogScan cut = scan_log_file(files[0]);
  EXPECT_EQ(static_cast<int>(cut.events.size()), static_cast<int>(scan.events.size()) - 1);
  EXPECT_GT(cut.torn_tail_bytes, 0);
  Child check({HS_BINARY_DIR "/bin/hs-logger", "--check", files[0]}, dir_ + "/check.txt");
  EXPECT_EQ(check.wait(), 0) << check.output();
  EXPECT_NE(check.output().find("\"torn_tail_bytes\": " + std::to_string(cut.torn_tail_bytes)),
            std::string::npos)
      << check.output();
  EXPECT_NE(check.output().find("\"lost_upstream\": 5"), std::string::npos) << check.output();
}

TEST_F(LoggerProcess, ACleanStopWritesTheManifestAndLcmLogplayerReplaysTheFile) {
  auto logger = start_logger();
  publish();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  logger->signal(SIGTERM);
  EXPECT_EQ(logger->wait(), 0) << logger->output();
  const std::vector<std::string> files = log_files();
  ASSERT_EQ(files.size(), 1u);
  std::ifstream in(files[0] + ".manifest.json");
  ASSERT_TRUE(in.good());
  const nlohmann::json manifest = nlohmann::json::parse(in);
  const int sent = kPoses - (kLostTo - kLostFrom + 1);
  EXPECT_EQ(manifest["channels"]["POSE"]["messages"], sent);
  EXPECT_EQ(manifest["channels"]["POSE"]["lost_upstream"], kLostTo - kLostFrom + 1);
  EXPECT_FALSE(manifest["channels"].contains("IGNORED_DEBUG"));

  // Stock lcm-logplayer publishes every recorded POSE again.
  const std::string replay_url = test::private_udpm_url(18);
  lcm::LCM sub(replay_url);
  ASSERT_TRUE(sub.good());
  int received = 0, sync = 0;
  sub.subscribeFunction(
      "POSE", +[](const lcm::ReceiveBuffer*, const std::string&, int* n) { ++*n; }, &received);
  sub.subscribeFunction(
      "HS_TEST_SYNC", +[](const lcm::ReceiveBuffer*, const std::string&, int* n) { ++*n; }, &sync);
  // udpm joins the group lazily: wait until a message reaches the subscriber.
  lcm::LCM ping(replay_url);
  ASSERT_TRUE(test::wait_for(
      [&] {
        ping.publish("HS_TEST_SYNC", "", 0);
        sub.handleTimeout(20);
        return sync > 0;
      },
      10));
  Child player({"lcm-logplayer", "-l", replay_url, files[0]}, dir_ + "/player.txt");
  ASSERT_TRUE(player.started());
  EXPECT_TRUE(test::wait_for(
      [&] {
        while (sub.handleTimeout(10) > 0) {
        }
        return received == sent;
      },
      20))
      << "received " << received << " of " << sent << "; " << player.output();
  player.wait();
}

TEST_F(LoggerProcess, WhatArrivedBeforeTheStopIsRecorded) {
  auto logger = start_logger();
  // Frozen, the logger leaves the messages in its socket buffer; SIGTERM then reaches it before
  // it has handled any of them.
  logger->signal(SIGSTOP);
  lcm::LCM pub(url_);
  ASSERT_TRUE(pub.good());
  constexpr int kSent = 20;
  for (int seq = 0; seq < kSent; ++seq) {
    hsslam::odometry_t m{};
    m.seq = seq;
    pub.publish("POSE", &m);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  logger->signal(SIGTERM);
  logger->signal(SIGCONT);
  EXPECT_EQ(logger->wait(), 0) << logger->output();
  const std::vector<std::string> files = log_files();
  ASSERT_EQ(files.size(), 1u);
  EXPECT_EQ(count_channel(scan_log_file(files[0]).events, "POSE"), kSent) << logger->output();
}

}  // namespace
}  // namespace hs
