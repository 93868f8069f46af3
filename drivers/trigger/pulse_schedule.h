#pragma once
// When hs-trigger pulses: at absolute times start + k / rate on CLOCK_MONOTONIC (no drift from
// the time each pulse takes). A deadline already missed by a whole period is skipped and
// counted (the cameras then miss that frame; pulsing late would expose it at the wrong time).
#include <cstdint>

namespace hs {

class PulseSchedule {
 public:
  PulseSchedule(int64_t start_ns, double rate_hz);
  // The next deadline at or after `now_ns` (skipping and counting missed ones).
  int64_t next(int64_t now_ns);
  int64_t skipped() const { return skipped_; }
  int64_t period_ns() const { return period_ns_; }

 private:
  int64_t start_ns_;
  double rate_hz_;
  int64_t period_ns_;
  int64_t k_ = 0;  // index of the next pulse
  int64_t skipped_ = 0;
  int64_t deadline(int64_t k) const;
};

// Phase lock: which data-ready edges get a pulse: every divider-th, counted from the first
// after a (re)start. Edges read together (the process was late) keep the count; a pulse due at
// an older one of them is still given, late (its loopback edge still times it), and counted.
class SyncDivider {
 public:
  explicit SyncDivider(int divider) : divider_(divider) {}
  // `pending` edges read at once: true when one of them is due a pulse.
  bool edges(int pending);
  void restart() { count_ = 0; }  // the data-ready line stalled: phase from the next edge
  int64_t late() const { return late_; }

 private:
  int divider_;
  int64_t count_ = 0;
  int64_t late_ = 0;
};

}  // namespace hs
