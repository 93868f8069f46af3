#include "tools/launch/supervisor.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>

#include "tests/dataset/dataset_test_util.h"
#include "tools/launch/status_table.h"

namespace hs {
namespace {

constexpr int64_t kMs = 1'000'000;

ProcessSpec shell(const std::string& name, const std::string& script) {
  ProcessSpec p;
  p.name = name;
  p.command = {"/bin/sh", "-c", script};
  return p;
}

// A supervisor over real child processes, driven by a synthetic clock that advances 10 ms per
// step while the children run in real time: every delay is exact on that clock.
class Harness {
 public:
  explicit Harness(std::vector<ProcessSpec> specs, RestartBackoff backoff = {}) {
    LaunchOptions o;
    o.log_dir = dir_.path() + "/logs";
    o.backoff = backoff;
    o.processes = std::move(specs);
    sup_ = std::make_unique<Supervisor>(o, "");
  }
  Supervisor& sup() { return *sup_; }
  int64_t now() const { return now_; }
  const std::string& dir() const { return dir_.path(); }
  const SupervisedProcess& proc(size_t i) const { return sup_->processes().at(i); }

  void step() {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    now_ += 10 * kMs;
    sup_->tick(now_);
    for (std::string& e : sup_->take_events()) events_.push_back(std::move(e));
  }
  // Steps until `pred` holds or 10 s of real time pass.
  template <class Pred>
  bool run_until(Pred&& pred) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!pred()) {
      if (std::chrono::steady_clock::now() > deadline) return false;
      step();
    }
    return true;
  }
  std::string events() const {
    std::string all;
    for (const std::string& e : events_) all += e + "\n";
    return all;
  }

 private:
  test::TempDir dir_;
  std::unique_ptr<Supervisor> sup_;
  int64_t now_ = 1'000'000'000;
  std::vector<std::string> events_;
};

bool process_exists(pid_t pid) {
  return ::kill(pid, 0) == 0;
}

TEST(Supervisor, CrashesAreRestartedWithDoublingDelayThenGivenUp) {
  RestartBackoff b;
  b.initial_ns = 100 * kMs;
  b.max_ns = 300 * kMs;
  b.max_failures = 4;
  Harness h({shell("crasher", "kill -SEGV $$")}, b);
  h.sup().start(h.now());
  std::vector<int64_t> delays;
  int64_t ended_at = 0;
  ASSERT_TRUE(h.run_until([&] {
    const SupervisedProcess& p = h.proc(0);
    if (p.state == ProcessState::kWaiting && ended_at == 0 && p.starts > 0) {
      ended_at = h.now();
      delays.push_back(p.next_start_ns - ended_at);
    }
    if (p.state == ProcessState::kRunning) ended_at = 0;
    return p.state == ProcessState::kGivenUp;
  })) << h.events();
  EXPECT_EQ(delays, (std::vector<int64_t>{100 * kMs, 200 * kMs, 300 * kMs}));
  EXPECT_EQ(h.proc(0).starts, 4);
  EXPECT_EQ(h.proc(0).last_reason, "signal 11 (Segmentation fault)");
  EXPECT_TRUE(h.sup().done());
  EXPECT_EQ(h.sup().exit_code(), 1);
  EXPECT_NE(h.events().find("given up after 4 failures in a row"), std::string::npos) << h.events();
}

TEST(Supervisor, RestartPoliciesDecideOnTheExitStatus) {
  ProcessSpec clean = shell("clean", "exit 0");
  ProcessSpec failing = shell("failing", "exit 3");
  failing.restart = RestartPolicy::kNever;
  ProcessSpec always = shell("always", "exit 0");
  always.restart = RestartPolicy::kAlways;
  RestartBackoff b;
  b.initial_ns = 50 * kMs;
  Harness h({clean, failing, always}, b);
  h.sup().start(h.now());
  ASSERT_TRUE(h.run_until([&] { return h.proc(2).starts >= 3; })) << h.events();
  EXPECT_EQ(h.proc(0).state, ProcessState::kEnded);  // on-failure, exit 0: done
  EXPECT_EQ(h.proc(0).starts, 1);
  EXPECT_EQ(h.proc(1).state, ProcessState::kEnded);  // never, exit 3: not restarted
  EXPECT_EQ(h.proc(1).last_reason, "exit 3");
  EXPECT_EQ(h.proc(2).failures_in_row, 0);  // clean exits are no failures: no backoff
  EXPECT_FALSE(h.sup().done());
}

TEST(Supervisor, StopSignalsEveryProcessAndKillsTheStubbornAfterItsTimeout) {
  ProcessSpec polite = shell("polite", "trap 'exit 0' TERM; while :; do sleep 0.05; done");
  ProcessSpec stubborn = shell("stubborn", "trap '' TERM; while :; do sleep 0.05; done");
  stubborn.stop_timeout_ns = 300 * kMs;
  Harness h({polite, stubborn});
  h.sup().start(h.now());
  ASSERT_TRUE(h.run_until([&] { return h.now() > 1'300'000'000; }));  // both shells set up
  const pid_t stubborn_pid = h.proc(1).pid;
  ASSERT_TRUE(process_exists(stubborn_pid));
  const int64_t stop_at = h.now();
  h.sup().stop(SIGTERM, stop_at);
  int64_t polite_end = 0;
  ASSERT_TRUE(h.run_until([&] {
    if (!polite_end && h.proc(0).state == ProcessState::kEnded) polite_end = h.now();
    return h.sup().done();
  })) << h.events();
  EXPECT_EQ(h.proc(0).last_reason, "exit 0");
  EXPECT_LT(polite_end - stop_at, 300 * kMs);
  EXPECT_EQ(h.proc(1).last_reason, "signal 9 (Killed)");
  EXPECT_GE(h.now() - stop_at, 300 * kMs);
  EXPECT_FALSE(process_exists(stubborn_pid));
  EXPECT_EQ(h.sup().exit_code(), 0);
  EXPECT_NE(h.events().find("stubborn (pid " + std::to_string(stubborn_pid) +
                            "): did not stop within 0.3 s: SIGKILL"),
            std::string::npos)
      << h.events();
}

TEST(Supervisor, ForwardedSignalsReachTheWholeProcessGroup) {
  test::TempDir d;
  const std::string marker = d.path() + "/usr1";
  // The signal reaches the inner shell, a grandchild of the supervisor.
  Harness h({shell("nested", "sh -c \"trap 'echo got >> " + marker +
                                 "; exit 0' USR1; while :; do sleep 0.05; done\"; exit 0")});
  h.sup().start(h.now());
  ASSERT_TRUE(h.run_until([&] { return h.now() > 1'300'000'000; }));
  h.sup().forward(SIGUSR1);
  ASSERT_TRUE(h.run_until([&] { return std::ifstream(marker).good(); }));
  std::ifstream in(marker);
  std::string word;
  in >> word;
  EXPECT_EQ(word, "got");
}

hsslam::heartbeat_t heartbeat(pid_t pid, const std::string& process) {
  hsslam::heartbeat_t hb{};
  hb.pid = pid;
  hb.process = process;
  hb.state = hsslam::heartbeat_t::OK;
  hb.message = "fine";
  hb.queue_names = {"frames", "imu"};
  hb.queue_depths = {1, 7};
  hb.num_queues = 2;
  return hb;
}

TEST(Supervisor, SilentHeartbeatMeansHungAndIsKilledAndRestarted) {
  ProcessSpec p = shell("worker", "while :; do sleep 0.05; done");
  p.heartbeat = "hs-worker";
  p.heartbeat_timeout_ns = 500 * kMs;
  RestartBackoff b;
  b.initial_ns = 50 * kMs;
  Harness h({p}, b);
  h.sup().start(h.now());
  const pid_t first = h.proc(0).pid;
  // Heartbeats from elsewhere (another pid, or our pid with another name) do not count.
  EXPECT_FALSE(h.sup().on_heartbeat(heartbeat(first + 100000, "hs-worker"), h.now()));
  EXPECT_FALSE(h.sup().on_heartbeat(heartbeat(first, "hs-other"), h.now()));
  // Ours keep it alive past the timeout.
  for (int i = 0; i < 100; ++i) {
    if (i % 20 == 0) {
      EXPECT_TRUE(h.sup().on_heartbeat(heartbeat(first, "hs-worker"), h.now()));
    }
    h.step();
  }
  EXPECT_EQ(h.proc(0).pid, first);
  EXPECT_EQ(h.proc(0).heartbeat.queues, "frames 1, imu 7");
  const std::vector<std::string> lines = format_status(h.sup().processes(), h.now());
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_NE(lines[0].find("OK"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("fine  [frames 1, imu 7]"), std::string::npos) << lines[0];
  // Then silence: killed and started again.
  ASSERT_TRUE(h.run_until([&] { return h.proc(0).starts == 2; })) << h.events();
  EXPECT_FALSE(process_exists(first));
  EXPECT_EQ(h.proc(0).last_reason, "hung, signal 9 (Killed)");
  EXPECT_NE(h.events().find("no HEARTBEAT for 0.5 s (hung): SIGKILL"), std::string::npos)
      << h.events();
  h.sup().stop(SIGTERM, h.now());
  ASSERT_TRUE(h.run_until([&] { return h.sup().done(); }));
}

TEST(Supervisor, StartAfterWaitsForTheHeartbeatOfEachRunAndIgnoresWhatDoesNotRun) {
  ProcessSpec logger = shell("logger", "while :; do sleep 0.05; done");
  logger.heartbeat = "hs-logger";
  ProcessSpec replay = shell("replay", "while :; do sleep 0.05; done");
  replay.start_after = {"logger", "viewer"};  // no viewer here: not waited for
  RestartBackoff b;
  b.initial_ns = 50 * kMs;
  Harness h({logger, replay}, b);
  h.sup().start(h.now());
  for (int i = 0; i < 20; ++i) h.step();
  EXPECT_EQ(h.proc(0).state, ProcessState::kRunning);
  EXPECT_EQ(h.proc(1).state, ProcessState::kWaiting);
  EXPECT_EQ(h.proc(1).starts, 0);
  EXPECT_NE(h.events().find("replay: waiting for the HEARTBEAT of logger\n"), std::string::npos)
      << h.events();
  ASSERT_TRUE(h.sup().on_heartbeat(heartbeat(h.proc(0).pid, "hs-logger"), h.now()));
  h.step();
  EXPECT_EQ(h.proc(1).state, ProcessState::kRunning);
  // The logger's next run must say it is up again before the replay's next start.
  ::kill(h.proc(0).pid, SIGKILL);
  ::kill(h.proc(1).pid, SIGKILL);
  ASSERT_TRUE(h.run_until([&] { return h.proc(0).starts == 2 && h.proc(1).last_exit; }))
      << h.events();
  for (int i = 0; i < 20; ++i) h.step();
  EXPECT_EQ(h.proc(1).starts, 1) << h.events();
  ASSERT_TRUE(h.sup().on_heartbeat(heartbeat(h.proc(0).pid, "hs-logger"), h.now()));
  ASSERT_TRUE(h.run_until([&] { return h.proc(1).starts == 2; })) << h.events();
  h.sup().stop(SIGTERM, h.now());
  ASSERT_TRUE(h.run_until([&] { return h.sup().done(); }));
}

TEST(Supervisor, ARequiredProcessEndingStopsTheOthers) {
  ProcessSpec replay = shell("replay", "sleep 0.2; exit 0");
  replay.restart = RestartPolicy::kNever;
  replay.required = true;
  Harness h({shell("service", "trap 'exit 0' TERM; while :; do sleep 0.05; done"), replay});
  h.sup().start(h.now());
  ASSERT_TRUE(h.run_until([&] { return h.sup().done(); })) << h.events();
  EXPECT_EQ(h.proc(0).last_reason, "exit 0");
  EXPECT_EQ(h.sup().exit_code(), 0);
  EXPECT_NE(h.events().find("required process ended: stopping all"), std::string::npos);
}

TEST(Supervisor, OutputGoesToTheProcessLogWithAStartLine) {
  RestartBackoff b;
  b.initial_ns = 50 * kMs;
  b.max_failures = 2;
  Harness h({shell("talker", "echo out; echo err >&2; exit 1")}, b);
  h.sup().start(h.now());
  ASSERT_TRUE(h.run_until([&] { return h.sup().done(); }));
  std::ifstream in(h.dir() + "/logs/talker.log");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string log = ss.str();
  EXPECT_NE(log.find("----- hs-launch: start 1 at "), std::string::npos) << log;
  EXPECT_NE(log.find("----- hs-launch: start 2 at "), std::string::npos) << log;
  EXPECT_NE(log.find("out\nerr\n"), std::string::npos) << log;
}

TEST(Supervisor, AMissingProgramIsReportedBeforeAnythingStarts) {
  LaunchOptions o;
  test::TempDir d;
  o.log_dir = d.path();
  o.processes = {shell("fine", "exit 0")};
  ProcessSpec missing;
  missing.name = "tracker";
  missing.command = {"hs-no-such-program"};
  o.processes.push_back(missing);
  try {
    Supervisor sup(o, "/nonexistent/bin");
    ADD_FAILURE() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("process 'tracker': program 'hs-no-such-program' not "
                                         "found beside hs-launch (/nonexistent/bin) or in PATH"),
              std::string::npos)
        << e.what();
  }
}

TEST(Spawn, ResolvesBesideTheLauncherFirstThenPath) {
  test::TempDir d;
  const std::string own = d.path() + "/sh";
  std::ofstream(own) << "#!/bin/sh\n";
  ::chmod(own.c_str(), 0755);
  EXPECT_EQ(resolve_program("sh", d.path()), own);
  EXPECT_EQ(resolve_program("sh", "/nonexistent"), resolve_program("sh", ""));
  EXPECT_FALSE(resolve_program("sh", "").empty());
  EXPECT_EQ(resolve_program(d.path() + "/missing", ""), "");
}

}  // namespace
}  // namespace hs
