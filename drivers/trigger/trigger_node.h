#pragma once
// hs-trigger's work: pulses the cameras' trigger line through libgpiod at the configured rate
// and publishes each pulse on TRIGGER with its sequence number and time. The time is the
// kernel's CLOCK_MONOTONIC timestamp of the pulse's rising edge read back on the edge line (a
// loopback or the cameras' strobe), or, without one, the time just before the line was set. A
// pulse whose edge does not come back is published with the set time and counted.
// Phase-locked (sync_line set), the pulses follow the IMU's data-ready edges instead of a clock:
// one on every sync_divider-th edge, so that frames keep a fixed phase to IMU samples; a stalled
// data-ready line is reported (no pulses meanwhile) and the phase starts anew when it resumes.
#include <lcm/lcm-cpp.hpp>

#include "drivers/trigger/trigger_options.h"

namespace hs {

struct TriggerStats {
  int64_t pulses = 0;
  int64_t edges = 0;             // pulses timed by their edge
  int64_t missing_edges = 0;     // no edge within edge_timeout
  int64_t skipped = 0;           // deadlines missed by a whole period
  double max_edge_delay_ms = 0;  // edge time minus set time
  int64_t sync_edges = 0;        // data-ready edges seen (phase-locked)
  int64_t sync_timeouts = 0;     // sync_timeout without one
  int64_t late_pulses = 0;       // given after a later data-ready edge had come
  double max_sync_delay_ms = 0;  // pulse time minus its data-ready edge's time
};

class TriggerNode {
 public:
  TriggerNode(lcm::LCM& lcm, TriggerOptions options);
  // Until stop_requested(); throws std::runtime_error when the chip or lines cannot be had.
  void run();
  const TriggerStats& stats() const { return stats_; }

 private:
  void publish_heartbeat(int8_t state);
  void heartbeat_if_due();

  lcm::LCM& lcm_;
  TriggerOptions options_;
  TriggerStats stats_;
  int64_t next_heartbeat_ns_ = 0;
};

}  // namespace hs
