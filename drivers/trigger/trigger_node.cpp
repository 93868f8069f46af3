#include "drivers/trigger/trigger_node.h"

#include <time.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <gpiod.hpp>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "common/core/monotonic_clock.h"
#include "common/core/stop_signal.h"
#include "common/lcm/process_loop.h"
#include "drivers/trigger/pulse_schedule.h"
#include "hsslam/trigger_t.hpp"

namespace hs {
namespace {

gpiod::line find_line(gpiod::chip& chip, const std::string& spec) {
  const bool number = !spec.empty() && std::all_of(spec.begin(), spec.end(),
                                                   [](unsigned char c) { return std::isdigit(c); });
  gpiod::line line = number ? chip.get_line(std::stoi(spec)) : chip.find_line(spec);
  if (!line) throw std::runtime_error("GPIO chip " + chip.name() + " has no line '" + spec + "'");
  return line;
}

// libgpiod throws when the wait is interrupted by a signal (the stop signal is installed without
// SA_RESTART so that waits end at once): that is no edge, and the loop then sees the stop.
bool wait_edge(const gpiod::line& line, int64_t timeout_ns) {
  try {
    return line.event_wait(std::chrono::nanoseconds(timeout_ns));
  } catch (const std::system_error& e) {
    if (e.code().value() == EINTR) return false;
    throw;
  }
}

void sleep_until(int64_t t_ns) {
  timespec ts{static_cast<time_t>(t_ns / 1'000'000'000), static_cast<long>(t_ns % 1'000'000'000)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR &&
         !stop_requested()) {
  }
}

}  // namespace

TriggerNode::TriggerNode(lcm::LCM& lcm, TriggerOptions options)
    : lcm_(lcm), options_(std::move(options)) {}

void TriggerNode::publish_heartbeat(int8_t state) {
  hsslam::heartbeat_t hb = heartbeat_header("hs-trigger", state);
  hb.message = "pulsing " + options_.chip + " line " + options_.output_line;
  if (!options_.sync_line.empty())
    hb.message += " on every " + std::to_string(options_.sync_divider) + "th edge of line " +
                  options_.sync_line;
  if (stats_.missing_edges > 0) hb.message += "; edges missing";
  if (stats_.sync_timeouts > 0) hb.message += "; data-ready edges stalled";
  const std::vector<std::pair<std::string, int64_t>> counters = {
      {"pulses", stats_.pulses},
      {"edges", stats_.edges},
      {"missing_edges", stats_.missing_edges},
      {"skipped", stats_.skipped},
      {"max_edge_delay_us", static_cast<int64_t>(stats_.max_edge_delay_ms * 1000)},
      {"sync_edges", stats_.sync_edges},
      {"sync_timeouts", stats_.sync_timeouts},
      {"late_pulses", stats_.late_pulses},
      {"max_sync_delay_us", static_cast<int64_t>(stats_.max_sync_delay_ms * 1000)}};
  add_counters(hb, counters);
  lcm_.publish(options_.channels.heartbeat, &hb);
}

void TriggerNode::heartbeat_if_due() {
  const int64_t now = monotonic_ns();
  if (now < next_heartbeat_ns_) return;
  const bool degraded = stats_.missing_edges > 0 || stats_.skipped > 0 || stats_.sync_timeouts > 0;
  publish_heartbeat(degraded ? hsslam::heartbeat_t::DEGRADED : hsslam::heartbeat_t::OK);
  next_heartbeat_ns_ = now + options_.heartbeat_period_ns;
}

void TriggerNode::run() {
  gpiod::chip chip;
  try {
    chip.open(options_.chip);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot open GPIO chip '" + options_.chip + "': " + e.what());
  }
  gpiod::line out = find_line(chip, options_.output_line);
  try {
    out.request({"hs-trigger", gpiod::line_request::DIRECTION_OUTPUT, 0}, 0);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot drive line '" + options_.output_line +
                             "' (busy?): " + e.what());
  }
  auto watch = [&](const std::string& name) {
    gpiod::line line = find_line(chip, name);
    try {
      line.request({"hs-trigger", gpiod::line_request::EVENT_RISING_EDGE, 0});
    } catch (const std::exception& e) {
      throw std::runtime_error("cannot watch line '" + name + "': " + e.what());
    }
    return line;
  };
  std::optional<gpiod::line> edge, sync;
  if (!options_.edge_line.empty()) edge = watch(options_.edge_line);
  if (!options_.sync_line.empty()) sync = watch(options_.sync_line);
  PulseSchedule schedule(monotonic_ns() + 100'000'000, options_.rate_hz);
  SyncDivider divider(options_.sync_divider);
  while (!stop_requested()) {
    int64_t sync_ns = -1;
    if (sync) {
      if (!wait_edge(*sync, options_.sync_timeout_ns)) {
        if (!stop_requested()) {
          ++stats_.sync_timeouts;
          divider.restart();
        }
        heartbeat_if_due();
        continue;
      }
      const std::vector<gpiod::line_event> events = sync->event_read_multiple();
      stats_.sync_edges += static_cast<int64_t>(events.size());
      const bool due = divider.edges(static_cast<int>(events.size()));
      stats_.late_pulses = divider.late();
      if (!due) {
        heartbeat_if_due();
        continue;
      }
      sync_ns = events.back().timestamp.count();
    } else {
      const int64_t deadline = schedule.next(monotonic_ns());
      stats_.skipped = schedule.skipped();
      sleep_until(deadline);
      if (stop_requested()) break;
    }
    const int64_t set_ns = monotonic_ns();
    out.set_value(1);
    int64_t t_ns = set_ns;
    if (edge) {
      // Edges left over from a pulse whose edge came too late are not this pulse's.
      while (wait_edge(*edge, 0)) edge->event_read();
      if (wait_edge(*edge, options_.edge_timeout_ns)) {
        const gpiod::line_event ev = edge->event_read();
        t_ns = ev.timestamp.count();
        ++stats_.edges;
        stats_.max_edge_delay_ms = std::max(stats_.max_edge_delay_ms, (t_ns - set_ns) / 1e6);
      } else {
        ++stats_.missing_edges;
      }
    }
    if (sync_ns >= 0)
      stats_.max_sync_delay_ms = std::max(stats_.max_sync_delay_ms, (t_ns - sync_ns) / 1e6);
    sleep_until(set_ns + options_.pulse_width_ns);
    out.set_value(0);
    hsslam::trigger_t msg;
    msg.t_ns = t_ns;
    msg.seq = stats_.pulses++;
    lcm_.publish(options_.channels.trigger, &msg);
    heartbeat_if_due();
  }
  publish_heartbeat(hsslam::heartbeat_t::STOPPING);
}

}  // namespace hs
