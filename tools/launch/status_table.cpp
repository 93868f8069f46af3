#include "tools/launch/status_table.h"

#include <algorithm>
#include <cstdio>

#include "common/core/types.h"
#include "hsslam/heartbeat_t.hpp"

namespace hs {
namespace {

std::string uptime(int64_t ns) {
  const long s = static_cast<long>(ns / 1'000'000'000);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  return buf;
}

std::string pad(std::string s, size_t width) {
  if (s.size() < width) s.append(width - s.size(), ' ');
  return s;
}

std::string heartbeat_text(const SupervisedProcess& p, int64_t now_ns) {
  const HeartbeatView& h = p.heartbeat;
  if (h.received_ns == 0) return p.spec.heartbeat.empty() ? "" : "no HEARTBEAT yet";
  char age[32];
  std::snprintf(age, sizeof age, "%.1f s ago", ns_to_s(now_ns - h.received_ns));
  std::string out = pad(heartbeat_state_name(h.state), 9) + pad(age, 11);
  if (!h.message.empty()) out += "  " + h.message;
  if (!h.queues.empty()) out += "  [" + h.queues + "]";
  return out;
}

}  // namespace

const char* heartbeat_state_name(int8_t state) {
  switch (state) {
    case hsslam::heartbeat_t::STARTING:
      return "STARTING";
    case hsslam::heartbeat_t::OK:
      return "OK";
    case hsslam::heartbeat_t::DEGRADED:
      return "DEGRADED";
    case hsslam::heartbeat_t::ERROR:
      return "ERROR";
    case hsslam::heartbeat_t::STOPPING:
      return "STOPPING";
  }
  return "UNKNOWN";
}

std::vector<std::string> format_status(const std::vector<SupervisedProcess>& processes,
                                       int64_t now_ns) {
  size_t name_width = 4;
  for (const SupervisedProcess& p : processes)
    name_width = std::max(name_width, p.spec.name.size());
  std::vector<std::string> lines;
  for (const SupervisedProcess& p : processes) {
    std::string line = pad(p.spec.name, name_width + 2) + pad(to_string(p.state), 10);
    switch (p.state) {
      case ProcessState::kRunning:
      case ProcessState::kStopping:
        line += pad("pid " + std::to_string(p.pid), 11) +
                pad("up " + uptime(now_ns - p.started_ns), 13);
        break;
      case ProcessState::kWaiting: {
        char in[48];
        std::snprintf(in, sizeof in, "start in %.1f s",
                      ns_to_s(std::max<int64_t>(0, p.next_start_ns - now_ns)));
        line += pad(in, 24);
        break;
      }
      default:
        line += pad("", 24);
    }
    line += pad("starts " + std::to_string(p.starts), 10);
    if (!p.last_reason.empty()) line += "last: " + pad(p.last_reason, 12) + "  ";
    if (p.state == ProcessState::kRunning || p.state == ProcessState::kStopping)
      line += heartbeat_text(p, now_ns);
    while (!line.empty() && line.back() == ' ') line.pop_back();
    lines.push_back(line);
  }
  return lines;
}

}  // namespace hs
