#pragma once
// The supervision of a set of processes on one machine (hs-launch): starts them in order,
// restarts the ones that end per their policy with exponential backoff, kills the ones whose
// HEARTBEAT falls silent (hung), forwards signals, and stops them all (stop signal, then SIGKILL
// after the process's stop timeout). Driven by tick(now) from the caller's loop; what happens is
// reported as human-readable events.
#include <sys/types.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hsslam/heartbeat_t.hpp"
#include "tools/launch/launch_options.h"
#include "tools/launch/spawn.h"

namespace hs {

enum class ProcessState {
  kWaiting,  // to be started at next_start_ns
  kRunning,
  kStopping,  // stop signal sent, SIGKILL at stop_deadline_ns
  kEnded,     // ended and not to be restarted
  kGivenUp,   // failed max_failures times in a row
};
const char* to_string(ProcessState state);

// The last HEARTBEAT of the current run.
struct HeartbeatView {
  int64_t received_ns = 0;  // 0: none yet
  int8_t state = 0;
  std::string message;
  std::string queues;  // "frames 0, imu_samples 3"
};

struct SupervisedProcess {
  ProcessSpec spec;
  std::string program;  // resolved path
  ProcessState state = ProcessState::kWaiting;
  pid_t pid = 0;
  int64_t started_ns = 0;
  int64_t next_start_ns = 0;
  bool waiting_reported = false;  // "waiting for ..." said for the pending start
  int64_t stop_deadline_ns = 0;
  bool killed = false;  // SIGKILL sent in this run (hung, or did not stop)
  bool hung = false;    // killed because its HEARTBEAT fell silent
  int starts = 0;
  int failures_in_row = 0;
  int64_t backoff_ns = 0;
  std::optional<ExitStatus> last_exit;
  std::string last_reason;  // why the last run ended, e.g. "signal 11 (Segmentation fault)"
  HeartbeatView heartbeat;
};

class Supervisor {
 public:
  // Keeps the enabled processes. Throws InputError when a program cannot be found (before
  // anything starts); creates the log directory.
  Supervisor(LaunchOptions options, const std::string& program_dir);

  void start(int64_t now_ns);
  void tick(int64_t now_ns);
  // True when it came from one of our processes (same pid, and the expected process name).
  bool on_heartbeat(const hsslam::heartbeat_t& hb, int64_t now_ns);
  void forward(int sig);  // to every running process's group
  // Stops everything: `sig` now, SIGKILL after each stop timeout; nothing restarts any more.
  void stop(int sig, int64_t now_ns);
  void kill_all();  // SIGKILL now (a second Ctrl-C)

  bool stopping() const { return stopping_; }
  bool done() const;      // nothing runs and nothing will start
  int exit_code() const;  // 1 if a process was given up or a required one failed, else 0
  const std::vector<SupervisedProcess>& processes() const { return processes_; }
  std::vector<std::string> take_events();

 private:
  void launch(SupervisedProcess& p, int64_t now_ns);
  // The start_after processes not yet running with a HEARTBEAT, as "a, b"; empty: none.
  std::string awaited(const SupervisedProcess& p) const;
  void on_exit(SupervisedProcess& p, const ExitStatus& status, int64_t now_ns);
  void schedule_restart(SupervisedProcess& p, bool failed, int64_t now_ns);
  void event(const SupervisedProcess& p, const std::string& what);

  LaunchOptions options_;
  std::vector<SupervisedProcess> processes_;
  std::vector<std::string> events_;
  bool stopping_ = false;
  bool required_failed_ = false;
};

}  // namespace hs
