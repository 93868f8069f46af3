#include "tools/launch/launch_options.h"

#include <algorithm>
#include <cctype>
#include <set>

#include "common/core/error.h"

namespace hs {
namespace {

RestartPolicy read_policy(ConfigSection& s, RestartPolicy fallback) {
  std::string name = to_string(fallback);
  s.read("restart", name);
  for (RestartPolicy p : {RestartPolicy::kNever, RestartPolicy::kOnFailure, RestartPolicy::kAlways})
    if (name == to_string(p)) return p;
  s.fail("restart", "must be never, on-failure or always, not '" + name + "'");
}

ProcessSpec read_process(ConfigSection& s, const std::string& name) {
  ProcessSpec p;
  p.name = name;
  p.command = s.require<std::vector<std::string>>("command");
  if (p.command.empty() || p.command[0].empty()) s.fail("command", "must name a program");
  s.read("enabled", p.enabled);
  p.restart = read_policy(s, p.restart);
  s.read("required", p.required);
  s.read("heartbeat", p.heartbeat);
  s.read_seconds("start_delay_s", p.start_delay_ns);
  if (p.start_delay_ns < 0) s.fail("start_delay_s", "must be >= 0");
  s.read("start_after", p.start_after);
  s.read_period("heartbeat_timeout_s", p.heartbeat_timeout_ns);
  s.read_period("stop_timeout_s", p.stop_timeout_ns);
  return p;
}

bool valid_name(const std::string& name) {
  if (name.empty()) return false;
  for (char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') return false;
  return true;
}

}  // namespace

const char* to_string(RestartPolicy policy) {
  switch (policy) {
    case RestartPolicy::kNever:
      return "never";
    case RestartPolicy::kOnFailure:
      return "on-failure";
    case RestartPolicy::kAlways:
      return "always";
  }
  return "?";
}

LaunchOptions load_launch_options(const std::string& path) {
  LaunchOptions o;
  ConfigSection top = ConfigSection::load(path);
  top.section("launch", [&](ConfigSection& s) {
    s.read("lcm_url", o.lcm_url);
    s.read("log_dir", o.log_dir);
    if (o.log_dir.empty()) s.fail("log_dir", "must not be empty");
    s.read_period("status_period_s", o.status_period_ns);
    s.read_seconds("status_log_period_s", o.status_log_period_ns);
    if (o.status_log_period_ns < 0) s.fail("status_log_period_s", "must be >= 0 (0: off)");
    s.read_period("heartbeat_period_s", o.heartbeat_period_ns);
  });
  top.section("restart", [&](ConfigSection& s) {
    RestartBackoff& b = o.backoff;
    s.read_period("delay_s", b.initial_ns);
    s.read_period("max_delay_s", b.max_ns);
    if (b.max_ns < b.initial_ns) s.fail("max_delay_s", "must be >= delay_s");
    s.read_period("stable_after_s", b.stable_after_ns);
    s.read("max_failures", b.max_failures);
    if (b.max_failures < 0) s.fail("max_failures", "must be >= 0 (0: never give up)");
  });
  top.section("processes", [&](ConfigSection& s) {
    for (const std::string& name : s.keys()) {
      if (!valid_name(name)) s.fail(name, "a process name is letters, digits, '-' and '_'");
      s.section(name, [&](ConfigSection& p) { o.processes.push_back(read_process(p, name)); });
    }
    // A start_after that no HEARTBEAT can ever satisfy would wait forever: refused here.
    for (const ProcessSpec& p : o.processes) {
      for (const std::string& after : p.start_after) {
        const auto it = std::find_if(o.processes.begin(), o.processes.end(),
                                     [&](const ProcessSpec& q) { return q.name == after; });
        if (it == o.processes.end() || it->name == p.name || it->heartbeat.empty())
          s.fail(p.name, "start_after: '" + after + "' must be another process with a heartbeat");
      }
    }
  });
  if (o.processes.empty()) top.fail("processes", "at least one process is needed");
  o.channels = read_channel_names(top);
  top.finish();
  return o;
}

void select_processes(LaunchOptions& options, const std::vector<std::string>& names) {
  std::set<std::string> wanted(names.begin(), names.end());
  std::string known;
  for (const ProcessSpec& p : options.processes) known += (known.empty() ? "" : ", ") + p.name;
  std::vector<ProcessSpec> kept;
  for (ProcessSpec& p : options.processes) {
    if (!wanted.erase(p.name)) continue;
    p.enabled = true;
    kept.push_back(std::move(p));
  }
  if (!wanted.empty())
    throw InputError("--only: no process named '" + *wanted.begin() + "' (known: " + known + ")");
  options.processes = std::move(kept);
}

}  // namespace hs
