#include "tools/launch/launch_options.h"

#include <gtest/gtest.h>

#include "tests/config/config_test_util.h"

namespace hs {
namespace {

using test::expect_input_error;
using test::TempYaml;

TEST(LaunchOptions, ShippedSystemConfigLoads) {
  const LaunchOptions o = load_launch_options(HS_SOURCE_DIR "/config/system.yaml");
  ASSERT_EQ(o.processes.size(), 5u);
  EXPECT_EQ(o.processes[0].name, "logger");  // file order is start order
  EXPECT_EQ(o.processes[2].name, "tracker");
  EXPECT_EQ(o.processes[2].heartbeat, "hs-tracker");
  EXPECT_EQ(o.processes[2].restart, RestartPolicy::kOnFailure);
  EXPECT_FALSE(o.processes[4].enabled);  // the replay
  EXPECT_TRUE(o.processes[4].required);
  EXPECT_EQ(o.processes[4].restart, RestartPolicy::kNever);
  EXPECT_EQ(o.processes[4].start_after, (std::vector<std::string>{"logger", "mapper", "tracker"}));
  EXPECT_EQ(o.backoff.max_failures, 10);
}

TEST(LaunchOptions, ReadsEveryKey) {
  TempYaml f(
      "launch:\n  lcm_url: memq://\n  log_dir: /tmp/x\n  status_log_period_s: 0\n"
      "restart:\n  delay_s: 0.25\n  max_delay_s: 2\n  stable_after_s: 5\n  max_failures: 0\n"
      "processes:\n  a:\n    command: [prog, -x]\n    restart: always\n    heartbeat: hs-a\n"
      "    heartbeat_timeout_s: 2.5\n    stop_timeout_s: 1\n    enabled: false\n");
  const LaunchOptions o = load_launch_options(f.path());
  EXPECT_EQ(o.lcm_url, "memq://");
  EXPECT_EQ(o.status_log_period_ns, 0);
  EXPECT_EQ(o.backoff.initial_ns, 250'000'000);
  EXPECT_EQ(o.backoff.max_failures, 0);
  ASSERT_EQ(o.processes.size(), 1u);
  const ProcessSpec& p = o.processes[0];
  EXPECT_EQ(p.command, (std::vector<std::string>{"prog", "-x"}));
  EXPECT_EQ(p.restart, RestartPolicy::kAlways);
  EXPECT_EQ(p.heartbeat_timeout_ns, 2'500'000'000);
  EXPECT_EQ(p.stop_timeout_ns, 1'000'000'000);
  EXPECT_FALSE(p.enabled);
}

TEST(LaunchOptions, BrokenConfigsAreClearErrors) {
  TempYaml policy("processes:\n  a:\n    command: [x]\n    restart: sometimes\n");
  expect_input_error([&] { load_launch_options(policy.path()); },
                     {policy.path() + ":4", "processes.a.restart", "on-failure", "sometimes"});
  TempYaml no_command("processes:\n  a:\n    restart: never\n");
  expect_input_error([&] { load_launch_options(no_command.path()); },
                     {"missing key 'processes.a.command'"});
  TempYaml empty_command("processes:\n  a:\n    command: []\n");
  expect_input_error([&] { load_launch_options(empty_command.path()); }, {"must name a program"});
  TempYaml typo("processes:\n  a:\n    command: [x]\n    hearbeat: hs-a\n");
  expect_input_error([&] { load_launch_options(typo.path()); },
                     {typo.path() + ":4", "did you mean 'heartbeat'"});
  TempYaml none("launch:\n  log_dir: x\n");
  expect_input_error([&] { load_launch_options(none.path()); }, {"at least one process"});
  TempYaml name("processes:\n  'a b':\n    command: [x]\n");
  expect_input_error([&] { load_launch_options(name.path()); }, {"letters, digits"});
  TempYaml dup("processes:\n  a:\n    command: [x]\n  a:\n    command: [y]\n");
  expect_input_error([&] { load_launch_options(dup.path()); }, {"duplicate key 'processes.a'"});
  TempYaml backoff(
      "restart:\n  delay_s: 2\n  max_delay_s: 1\nprocesses:\n  a:\n    command: [x]\n");
  expect_input_error([&] { load_launch_options(backoff.path()); }, {">= delay_s"});
  TempYaml after_silent(
      "processes:\n  a:\n    command: [x]\n  b:\n    command: [y]\n    start_after: [a]\n");
  expect_input_error([&] { load_launch_options(after_silent.path()); },
                     {"processes.b", "start_after: 'a' must be another process with a heartbeat"});
  TempYaml after_unknown(
      "processes:\n  a:\n    command: [x]\n    heartbeat: hs-a\n    start_after: [c]\n");
  expect_input_error([&] { load_launch_options(after_unknown.path()); }, {"start_after: 'c'"});
}

TEST(LaunchOptions, OnlySelectsNamedProcessesEvenDisabledOnes) {
  LaunchOptions o = load_launch_options(HS_SOURCE_DIR "/config/system.yaml");
  select_processes(o, {"replay", "logger"});
  ASSERT_EQ(o.processes.size(), 2u);
  EXPECT_EQ(o.processes[0].name, "logger");  // config order kept
  EXPECT_EQ(o.processes[1].name, "replay");
  EXPECT_TRUE(o.processes[1].enabled);
  LaunchOptions again = load_launch_options(HS_SOURCE_DIR "/config/system.yaml");
  expect_input_error(
      [&] { select_processes(again, {"trakcer"}); },
      {"no process named 'trakcer'", "known: logger, mapper, tracker, viewer, replay"});
}

}  // namespace
}  // namespace hs
