#pragma once
// All options of hs-launch, from one YAML file (config/system.yaml documents every key).
#include <cstdint>
#include <string>
#include <vector>

#include "common/config/channels.h"

namespace hs {

enum class RestartPolicy { kNever, kOnFailure, kAlways };

// One supervised program. The command is executed directly (no shell), so the child's pid is
// the program's own and its HEARTBEAT can be told apart by pid.
struct ProcessSpec {
  std::string name;  // unique; also the log file name
  std::vector<std::string>
      command;          // argv; a bare argv[0] is looked up beside hs-launch, then in PATH
  bool enabled = true;  // started unless --only names others
  RestartPolicy restart = RestartPolicy::kOnFailure;
  bool required = false;                 // when it ends for good, everything stops
  int64_t start_delay_ns = 0;            // first start this long after hs-launch's
  std::vector<std::string> start_after;  // each start waits until these run and sent a HEARTBEAT
  std::string heartbeat;                 // its heartbeat_t.process; empty: sends none
  int64_t heartbeat_timeout_ns = 5'000'000'000;  // silent this long: hung, killed, restarted
  int64_t stop_timeout_ns = 5'000'000'000;       // SIGKILL this long after the stop signal
};

// Restarts wait initial, then twice as long after each failure in a row up to max; a process that
// ran stable_after without failing starts over at initial. After max_failures failures in a row
// it is given up (0: never).
struct RestartBackoff {
  int64_t initial_ns = 500'000'000;
  int64_t max_ns = 10'000'000'000;
  int64_t stable_after_ns = 30'000'000'000;
  int max_failures = 10;
};

struct LaunchOptions {
  std::string lcm_url;  // given to every child as LCM_DEFAULT_URL; empty: hs-launch's own default
  std::string log_dir = "logs/launch";            // DIR/NAME.log: each process's stdout and stderr
  int64_t status_period_ns = 1'000'000'000;       // status redraw on a terminal
  int64_t status_log_period_ns = 10'000'000'000;  // not a terminal: the table this often (0: off)
  int64_t heartbeat_period_ns = 1'000'000'000;    // hs-launch's own HEARTBEAT
  RestartBackoff backoff;
  std::vector<ProcessSpec> processes;  // started in this order, stopped in reverse
  ChannelNames channels;
};

// Unknown keys, wrong types, bad values or duplicate names: InputError with file:line.
LaunchOptions load_launch_options(const std::string& path);

// Keeps exactly the named processes, enabled or not (hs-launch --only). InputError naming an
// unknown one.
void select_processes(LaunchOptions& options, const std::vector<std::string>& names);

const char* to_string(RestartPolicy policy);

}  // namespace hs
