// hs-launch as a process supervising the real hs-logger and stock lcm-logplayer over udpm on
// loopback: restart after kill -9, hang detection (SIGSTOP silences the HEARTBEAT), giving up on
// a crash loop, SIGUSR1 forwarding, stop escalation, SIGHUP as a stop, a required replay ending the
// run, and hs-launch's own HEARTBEAT.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <mutex>
#include <regex>
#include <sstream>
#include <thread>

#include "hsslam/heartbeat_t.hpp"
#include "tests/common/child_process.h"
#include "tests/common/process_test_util.h"
#include "tests/dataset/dataset_test_util.h"

namespace hs {
namespace {

namespace fs = std::filesystem;
using Child = test::ChildProcess;

// The pid in the newest "NAME (pid N): <what>" line of hs-launch's output, or 0.
pid_t pid_of(const std::string& output, const std::string& name, const std::string& what) {
  const std::regex re(name + " \\(pid ([0-9]+)\\): " + what);
  pid_t pid = 0;
  for (auto it = std::sregex_iterator(output.begin(), output.end(), re);
       it != std::sregex_iterator(); ++it)
    pid = std::stoi((*it)[1]);
  return pid;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

class LaunchProcess : public ::testing::Test {
 protected:
  std::unique_ptr<Child> launch(const std::string& yaml) {
    std::ofstream(dir_ + "/system.yaml") << yaml;
    auto child = std::make_unique<Child>(
        std::vector<std::string>{HS_LAUNCH, dir_ + "/system.yaml", "--status", "log"},
        dir_ + "/launch.txt");
    EXPECT_TRUE(child->started());
    return child;
  }
  std::string header(double status_period_s) const {
    return "launch:\n  lcm_url: \"" + url_ + "\"\n  log_dir: " + dir_ + "/launch\n" +
           "  status_log_period_s: " + std::to_string(status_period_s) + "\n" +
           "restart:\n  delay_s: 0.2\n  max_failures: 3\n";
  }

  test::TempDir tmp_;
  std::string dir_ = tmp_.path();
  std::string url_ = test::private_udpm_url(23);
};

TEST_F(LaunchProcess, RestartsKilledAndHungProcessesGivesUpOnCrashLoopsAndStopsEverything) {
  auto launcher = launch(
      header(0.5) + "processes:\n" + "  logger:\n    command: [hs-logger, --dir, " + dir_ +
      "/logs]\n" + "    heartbeat: hs-logger\n    heartbeat_timeout_s: 2.5\n" +
      "  crasher:\n    command: [/bin/sh, -c, 'sleep 0.2; kill -SEGV $$']\n" +
      "  stubborn:\n    command: [/bin/sh, -c, \"trap '' TERM; while :; do sleep 0.1; done\"]\n" +
      "    stop_timeout_s: 1\n");
  // hs-launch's own HEARTBEAT, as lcm-spy would show it.
  lcm::LCM lcm(url_);
  ASSERT_TRUE(lcm.good());
  struct LauncherHeartbeat {
    std::mutex mutex;
    std::string message;
  } seen;
  lcm.subscribeFunction(
      "HEARTBEAT",
      +[](const lcm::ReceiveBuffer*, const std::string&, const hsslam::heartbeat_t* hb,
          LauncherHeartbeat* out) {
        std::lock_guard<std::mutex> lock(out->mutex);
        if (hb->process == "hs-launch") out->message = hb->message;
      },
      &seen);
  std::atomic<bool> listening{true};
  std::thread receiver([&] {
    while (listening) lcm.handleTimeout(50);
  });

  // The logger runs and its HEARTBEAT shows in the status table.
  const auto heartbeat_ok = [&](const std::string& pid) {
    return test::wait_for(
        [&] {
          return std::regex_search(launcher->output(),
                                   std::regex("\n  logger +running +pid " + pid + " .* OK "));
        },
        15);
  };
  ASSERT_TRUE(heartbeat_ok("[0-9]+")) << launcher->output();
  const pid_t first = pid_of(launcher->output(), "logger", "started");
  ASSERT_GT(first, 0);

  // kill -9: restarted with a new pid.
  ::kill(first, SIGKILL);
  ASSERT_TRUE(test::wait_for(
      [&] { return pid_of(launcher->output(), "logger", "restarted \\(start 2\\)") > 0; }, 10))
      << launcher->output();
  const pid_t second = pid_of(launcher->output(), "logger", "restarted \\(start 2\\)");
  EXPECT_NE(second, first);

  // Hung (stopped): its HEARTBEAT falls silent, it is killed and started again.
  ASSERT_TRUE(test::wait_for(
      [&] { return contains(launcher->output(), "(pid " + std::to_string(second) + ")"); }, 5));
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // it has sent a HEARTBEAT
  ::kill(second, SIGSTOP);
  ASSERT_TRUE(test::wait_for(
      [&] { return pid_of(launcher->output(), "logger", "restarted \\(start 3\\)") > 0; }, 10))
      << launcher->output();
  EXPECT_TRUE(contains(launcher->output(),
                       "logger (pid " + std::to_string(second) + "): no HEARTBEAT for 2."))
      << launcher->output();
  const pid_t third = pid_of(launcher->output(), "logger", "restarted \\(start 3\\)");
  ASSERT_TRUE(heartbeat_ok(std::to_string(third))) << launcher->output();

  // The crash loop is given up after max_failures.
  ASSERT_TRUE(test::wait_for(
      [&] { return contains(launcher->output(), "crasher: given up after 3 failures in a row"); },
      10))
      << launcher->output();
  EXPECT_TRUE(contains(launcher->output(), "ended: signal 11 (Segmentation fault)"));

  {
    std::lock_guard<std::mutex> lock(seen.mutex);
    EXPECT_TRUE(contains(seen.message, "logger running")) << seen.message;
    EXPECT_TRUE(contains(seen.message, "crasher given-up")) << seen.message;
  }

  // SIGTERM stops all; the one that ignores it is killed after its stop timeout.
  const pid_t stubborn = pid_of(launcher->output(), "stubborn", "started");
  launcher->signal(SIGTERM);
  ASSERT_TRUE(test::wait_for([&] { return !launcher->running(); }, 10)) << launcher->output();
  EXPECT_EQ(launcher->wait(), 1) << "a given-up process makes the exit status 1";
  const std::string out = launcher->output();
  EXPECT_TRUE(contains(out, "logger (pid " + std::to_string(third) + "): ended: exit 0")) << out;
  EXPECT_TRUE(contains(
      out, "stubborn (pid " + std::to_string(stubborn) + "): did not stop within 1.0 s: SIGKILL"))
      << out;
  for (pid_t pid : {first, second, third, stubborn}) EXPECT_NE(::kill(pid, 0), 0) << pid;
  listening = false;
  receiver.join();

  // Every start is marked in the process's log, and the logger wrote files.
  std::ifstream in(dir_ + "/launch/logger.log");
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_TRUE(contains(ss.str(), "----- hs-launch: start 3 at ")) << ss.str();
  EXPECT_FALSE(fs::is_empty(dir_ + "/logs"));
}

TEST_F(LaunchProcess, ARequiredReplayEndsTheRunAndTheLoggerRecordedAllOfIt) {
  constexpr int kEvents = 40;
  const std::string log = dir_ + "/replay.lcmlog";
  {
    lcm::LogFile file(log, "w");
    ASSERT_TRUE(file.good());
    for (int i = 0; i < kEvents; ++i) {
      std::string data = "event " + std::to_string(i);
      lcm::LogEvent e{};
      e.eventnum = i;
      e.timestamp = 1'000'000 + 10'000 * i;
      e.channel = "REPLAYED";
      e.datalen = static_cast<int32_t>(data.size());
      e.data = data.data();
      ASSERT_EQ(file.writeEvent(&e), 0);
    }
  }
  auto launcher = launch(
      header(0) + "processes:\n" + "  logger:\n    command: [hs-logger, --dir, " + dir_ +
      "/logs]\n" + "    heartbeat: hs-logger\n" + "  replay:\n    command: [lcm-logplayer, " + log +
      "]\n" + "    restart: never\n    required: true\n    start_after: [logger]\n");
  ASSERT_TRUE(test::wait_for([&] { return !launcher->running(); }, 20)) << launcher->output();
  EXPECT_EQ(launcher->wait(), 0) << launcher->output();
  EXPECT_TRUE(contains(launcher->output(), "replay: required process ended: stopping all"))
      << launcher->output();
  // The replay started once the logger had subscribed, and the logger wrote what it had received
  // before the stop: every event, in order.
  std::vector<std::string> files;  // named by their start time
  for (const auto& entry : fs::directory_iterator(dir_ + "/logs"))
    if (entry.path().extension() == ".lcmlog") files.push_back(entry.path().string());
  std::sort(files.begin(), files.end());
  std::string replayed;
  for (const std::string& path : files) {
    lcm::LogFile file(path, "r");
    while (const lcm::LogEvent* e = file.readNextEvent()) {
      if (e->channel == "REPLAYED")
        replayed += std::string(static_cast<const char*>(e->data), e->datalen) + "\n";
    }
  }
  std::string expected;
  for (int i = 0; i < kEvents; ++i) expected += "event " + std::to_string(i) + "\n";
  EXPECT_EQ(replayed, expected) << launcher->output();
}

TEST_F(LaunchProcess, ForwardsUsr1AndAHangupStopsEverythingWithSigterm) {
  const std::string marker = dir_ + "/usr1";
  auto launcher = launch(header(0) + "processes:\n  sleeper:\n    command: [/bin/sleep, 30]\n" +
                         "  listener:\n    command: [/bin/sh, -c, \"trap 'echo usr1 >> " + marker +
                         "' USR1; while :; do sleep 0.1; done\"]\n");
  ASSERT_TRUE(
      test::wait_for([&] { return pid_of(launcher->output(), "listener", "started") > 0; }, 5));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the shell has set its trap
  launcher->signal(SIGUSR1);
  ASSERT_TRUE(test::wait_for([&] { return std::ifstream(marker).good(); }, 5))
      << launcher->output();
  launcher->signal(SIGHUP);
  ASSERT_TRUE(test::wait_for([&] { return !launcher->running(); }, 5)) << launcher->output();
  EXPECT_EQ(launcher->wait(), 0);
  EXPECT_TRUE(contains(launcher->output(), "SIGHUP: stopping all")) << launcher->output();
  EXPECT_TRUE(contains(launcher->output(), "ended: signal 15 (Terminated)")) << launcher->output();
}

TEST_F(LaunchProcess, ABrokenConfigOrMissingProgramStartsNothing) {
  auto bad = launch("processes:\n  a:\n    command: [x]\n    restart: allways\n");
  EXPECT_EQ(bad->wait(), 2);
  EXPECT_TRUE(contains(bad->output(), "system.yaml:4: 'processes.a.restart'")) << bad->output();
  auto missing = launch(header(0) + "processes:\n  ok:\n    command: [/bin/sleep, 30]\n" +
                        "  tracker:\n    command: [hs-no-such-program]\n");
  EXPECT_EQ(missing->wait(), 2);
  EXPECT_TRUE(contains(missing->output(), "program 'hs-no-such-program' not found"))
      << missing->output();
  EXPECT_FALSE(contains(missing->output(), "started")) << missing->output();
}

}  // namespace
}  // namespace hs
