#include "tools/launch/supervisor.h"

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>

#include "common/core/error.h"
#include "common/core/types.h"
#include "common/core/wall_clock.h"

namespace hs {
namespace {

std::string seconds_text(int64_t ns) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f s", ns_to_s(ns));
  return buf;
}

std::string join(const std::vector<std::string>& parts, const char* separator = " ") {
  std::string out;
  for (const std::string& p : parts) out += (out.empty() ? "" : separator) + p;
  return out;
}

bool alive(ProcessState s) {
  return s == ProcessState::kRunning || s == ProcessState::kStopping;
}

}  // namespace

const char* to_string(ProcessState state) {
  switch (state) {
    case ProcessState::kWaiting:
      return "waiting";
    case ProcessState::kRunning:
      return "running";
    case ProcessState::kStopping:
      return "stopping";
    case ProcessState::kEnded:
      return "ended";
    case ProcessState::kGivenUp:
      return "given-up";
  }
  return "?";
}

Supervisor::Supervisor(LaunchOptions options, const std::string& program_dir)
    : options_(std::move(options)) {
  for (const ProcessSpec& spec : options_.processes) {
    if (!spec.enabled) continue;
    SupervisedProcess p;
    p.spec = spec;
    p.program = resolve_program(spec.command[0], program_dir);
    if (p.program.empty())
      throw InputError("process '" + spec.name + "': program '" + spec.command[0] + "' not found" +
                       (spec.command[0].find('/') == std::string::npos
                            ? " beside hs-launch (" + program_dir + ") or in PATH"
                            : " or not executable"));
    p.backoff_ns = options_.backoff.initial_ns;
    processes_.push_back(std::move(p));
  }
  // Only the processes that run are waited for (a replay with --only logger replay).
  for (SupervisedProcess& p : processes_) {
    std::vector<std::string>& after = p.spec.start_after;
    after.erase(std::remove_if(after.begin(), after.end(),
                               [&](const std::string& name) {
                                 return std::none_of(processes_.begin(), processes_.end(),
                                                     [&](const SupervisedProcess& q) {
                                                       return q.spec.name == name;
                                                     });
                               }),
                after.end());
  }
  std::error_code ec;
  std::filesystem::create_directories(options_.log_dir, ec);
  if (ec) throw InputError(options_.log_dir, "cannot create the log directory: " + ec.message());
}

void Supervisor::start(int64_t now_ns) {
  for (SupervisedProcess& p : processes_) p.next_start_ns = now_ns + p.spec.start_delay_ns;
  tick(now_ns);
}

void Supervisor::event(const SupervisedProcess& p, const std::string& what) {
  events_.push_back(p.spec.name + (p.pid > 0 ? " (pid " + std::to_string(p.pid) + ")" : "") + ": " +
                    what);
}

std::vector<std::string> Supervisor::take_events() {
  return std::exchange(events_, {});
}

std::string Supervisor::awaited(const SupervisedProcess& p) const {
  std::vector<std::string> names;
  for (const std::string& after : p.spec.start_after) {
    for (const SupervisedProcess& q : processes_) {
      if (q.spec.name == after && !(q.state == ProcessState::kRunning && q.heartbeat.received_ns))
        names.push_back(after);
    }
  }
  return join(names, ", ");
}

void Supervisor::launch(SupervisedProcess& p, int64_t now_ns) {
  SpawnRequest request;
  request.program = p.program;
  request.argv = p.spec.command;
  request.log_path = options_.log_dir + "/" + p.spec.name + ".log";
  if (!options_.lcm_url.empty()) request.env.emplace_back("LCM_DEFAULT_URL", options_.lcm_url);
  std::ofstream(request.log_path, std::ios::app)
      << "----- hs-launch: start " << p.starts + 1 << " at "
      << wall_clock_text("%Y-%m-%dT%H:%M:%SZ", TimeZone::kUtc) << ": " << join(p.spec.command)
      << "\n";
  p.pid = 0;
  p.heartbeat = HeartbeatView{};
  p.killed = false;
  p.hung = false;
  try {
    p.pid = spawn_process(request);
  } catch (const std::exception& e) {
    event(p, e.what());
    p.last_reason = e.what();
    schedule_restart(p, true, now_ns);
    return;
  }
  ++p.starts;
  p.state = ProcessState::kRunning;
  p.started_ns = now_ns;
  event(p, p.starts == 1 ? "started" : "restarted (start " + std::to_string(p.starts) + ")");
}

void Supervisor::schedule_restart(SupervisedProcess& p, bool failed, int64_t now_ns) {
  const RestartBackoff& b = options_.backoff;
  if (failed) ++p.failures_in_row;
  if (b.max_failures > 0 && p.failures_in_row >= b.max_failures) {
    p.state = ProcessState::kGivenUp;
    event(p, "given up after " + std::to_string(p.failures_in_row) + " failures in a row");
    return;
  }
  const int64_t delay = failed ? p.backoff_ns : b.initial_ns;
  if (failed) p.backoff_ns = std::min(2 * p.backoff_ns, b.max_ns);
  p.state = ProcessState::kWaiting;
  p.next_start_ns = now_ns + delay;
  event(p, "restart in " + seconds_text(delay));
}

void Supervisor::on_exit(SupervisedProcess& p, const ExitStatus& status, int64_t now_ns) {
  const bool was_stopping = p.state == ProcessState::kStopping;
  p.last_exit = status;
  p.last_reason = p.hung ? "hung, " + describe(status) : describe(status);
  event(p, "ended: " + p.last_reason + " after " + seconds_text(now_ns - p.started_ns));
  p.pid = 0;
  const bool failed = !status.success() || p.killed;
  if (now_ns - p.started_ns >= options_.backoff.stable_after_ns) {
    p.failures_in_row = 0;
    p.backoff_ns = options_.backoff.initial_ns;
  }
  const RestartPolicy policy = p.spec.restart;
  const bool restart =
      !stopping_ && !was_stopping &&
      (policy == RestartPolicy::kAlways || (policy == RestartPolicy::kOnFailure && failed));
  if (restart) {
    schedule_restart(p, failed, now_ns);
  } else {
    p.state = ProcessState::kEnded;
  }
  if (p.spec.required && !stopping_ &&
      (p.state == ProcessState::kEnded || p.state == ProcessState::kGivenUp)) {
    required_failed_ = failed;
    event(p, "required process ended: stopping all");
    stop(SIGTERM, now_ns);
  }
}

void Supervisor::tick(int64_t now_ns) {
  for (SupervisedProcess& p : processes_) {
    if (alive(p.state)) {
      if (const std::optional<ExitStatus> status = try_reap(p.pid)) {
        on_exit(p, *status, now_ns);
        continue;
      }
    }
    if (p.state == ProcessState::kRunning && !p.spec.heartbeat.empty() && !p.killed) {
      const int64_t last = p.heartbeat.received_ns > 0 ? p.heartbeat.received_ns : p.started_ns;
      if (now_ns - last > p.spec.heartbeat_timeout_ns) {
        event(p, "no HEARTBEAT for " + seconds_text(now_ns - last) + " (hung): SIGKILL");
        p.killed = p.hung = true;
        signal_group(p.pid, SIGKILL);
      }
    }
    if (p.state == ProcessState::kStopping && !p.killed && now_ns >= p.stop_deadline_ns) {
      event(p, "did not stop within " + seconds_text(p.spec.stop_timeout_ns) + ": SIGKILL");
      p.killed = true;
      signal_group(p.pid, SIGKILL);
    }
    if (p.state == ProcessState::kWaiting && !stopping_ && now_ns >= p.next_start_ns) {
      const std::string missing = awaited(p);
      if (missing.empty()) {
        p.waiting_reported = false;
        launch(p, now_ns);
      } else if (!p.waiting_reported) {
        p.waiting_reported = true;
        event(p, "waiting for the HEARTBEAT of " + missing);
      }
    }
  }
}

bool Supervisor::on_heartbeat(const hsslam::heartbeat_t& hb, int64_t now_ns) {
  for (SupervisedProcess& p : processes_) {
    if (!alive(p.state) || p.pid != hb.pid) continue;
    if (!p.spec.heartbeat.empty() && hb.process != p.spec.heartbeat) continue;
    HeartbeatView& v = p.heartbeat;
    v.received_ns = now_ns;
    v.state = hb.state;
    v.message = hb.message;
    v.queues.clear();
    const size_t n = std::min(hb.queue_names.size(), hb.queue_depths.size());
    for (size_t i = 0; i < n; ++i)
      v.queues += (i ? ", " : "") + hb.queue_names[i] + " " + std::to_string(hb.queue_depths[i]);
    return true;
  }
  return false;
}

void Supervisor::forward(int sig) {
  for (const SupervisedProcess& p : processes_)
    if (alive(p.state)) signal_group(p.pid, sig);
}

void Supervisor::stop(int sig, int64_t now_ns) {
  stopping_ = true;
  for (auto it = processes_.rbegin(); it != processes_.rend(); ++it) {
    SupervisedProcess& p = *it;
    if (p.state == ProcessState::kWaiting) p.state = ProcessState::kEnded;
    if (p.state != ProcessState::kRunning) continue;
    p.state = ProcessState::kStopping;
    p.stop_deadline_ns = now_ns + p.spec.stop_timeout_ns;
    signal_group(p.pid, sig);
  }
}

void Supervisor::kill_all() {
  for (SupervisedProcess& p : processes_) {
    if (!alive(p.state)) continue;
    p.killed = true;
    signal_group(p.pid, SIGKILL);
  }
}

bool Supervisor::done() const {
  for (const SupervisedProcess& p : processes_)
    if (p.state != ProcessState::kEnded && p.state != ProcessState::kGivenUp) return false;
  return true;
}

int Supervisor::exit_code() const {
  if (required_failed_) return 1;
  for (const SupervisedProcess& p : processes_)
    if (p.state == ProcessState::kGivenUp) return 1;
  return 0;
}

}  // namespace hs
