#pragma once
// What every HS-SLAM LCM process does between start and stop: handle messages until SIGINT or
// SIGTERM (install_stop_signals() first), calling `poll` (heartbeats) between handle()s; and the
// fields every heartbeat_t starts with.
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <stdexcept>
#include <string>

#include "common/core/monotonic_clock.h"
#include "common/core/stop_signal.h"
#include "hsslam/heartbeat_t.hpp"

namespace hs {

// Throws std::runtime_error when LCM fails to receive.
template <class Poll>
void handle_until_stopped(lcm::LCM& lcm, Poll&& poll) {
  while (!stop_requested()) {
    if (lcm.handleTimeout(100) < 0 && !stop_requested())
      throw std::runtime_error("LCM receive failed");
    poll();
  }
}

// Handles the messages already received when a stop was asked for, for up to max_ms: a recorder
// stopped right after the last message was sent still has it in its socket buffer. It ends after
// quiet_ms without a message, not at the first empty poll: liblcm's udpm reads the socket in a
// reader thread of its own, and a process resumed (SIGCONT) with a stop pending polled before
// that thread had read anything (CI lost all 20 messages of the logger test so, once).
inline int drain_received(lcm::LCM& lcm, int max_ms, int quiet_ms = 100) {
  const int64_t end_ns = monotonic_ns() + int64_t{1'000'000} * max_ms;
  int handled = 0;
  for (int64_t left_ms = max_ms; left_ms > 0; left_ms = (end_ns - monotonic_ns()) / 1'000'000) {
    if (lcm.handleTimeout(static_cast<int>(std::min<int64_t>(quiet_ms, left_ms))) <= 0) break;
    ++handled;
  }
  return handled;
}

// t_ns (host CLOCK_MONOTONIC), process, pid and state; queues and counters left empty.
inline hsslam::heartbeat_t heartbeat_header(const std::string& process, int8_t state) {
  hsslam::heartbeat_t hb{};
  hb.t_ns = monotonic_ns();
  hb.process = process;
  hb.pid = static_cast<int32_t>(::getpid());
  hb.state = state;
  return hb;
}

// Appends named cumulative counters (pairs of name and value) to a heartbeat.
template <class Counters>
void add_counters(hsslam::heartbeat_t& hb, const Counters& counters) {
  for (const auto& [name, value] : counters) {
    hb.counter_names.emplace_back(name);
    hb.counter_values.push_back(value);
  }
  hb.num_counters = static_cast<int32_t>(hb.counter_names.size());
}

}  // namespace hs
