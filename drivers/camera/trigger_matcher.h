#pragma once
// External-trigger mode: each frame is matched with the TRIGGER pulse that exposed it. Pulses and
// frames are related by sequence (trigger seq = frame seq + offset); the offset is learnt from the
// first frame whose buffer time follows a pulse within max_latency, and every match is checked
// the same way (a buffer stamped before its pulse, or too long after, is not that pulse's frame).
// A frame that fails the check but plausibly follows exactly one other pulse relocks the offset
// there at once (the camera missed a pulse), waiting for that pulse's message if need be;
// ambiguous ones relock after relock_after mismatches in a row.
// TRIGGER messages may arrive after the frame (LCM), so a frame may wait for max_wait.
#include <cstdint>
#include <deque>
#include <optional>

namespace hs {

struct TriggerMatcherOptions {
  int64_t max_latency_ns = 40'000'000;  // pulse to buffer timestamp (exposure + readout + DMA)
  int64_t max_wait_ns = 100'000'000;    // how long a frame waits for its TRIGGER message
  size_t max_triggers = 100;            // pulses kept for matching
  int relock_after = 3;                 // mismatches in a row before the offset is learnt anew
};

struct TriggerMatchStats {
  int64_t matched = 0;
  int64_t frames_without_trigger = 0;
  int64_t triggers_without_frame = 0;
  int64_t time_mismatches = 0;
  int64_t relocks = 0;

  TriggerMatchStats& operator+=(const TriggerMatchStats& o) {
    matched += o.matched;
    frames_without_trigger += o.frames_without_trigger;
    triggers_without_frame += o.triggers_without_frame;
    time_mismatches += o.time_mismatches;
    relocks += o.relocks;
    return *this;
  }
};

enum class TriggerDecision { kMatched, kWait, kNoTrigger, kTimeMismatch };

struct TriggerMatch {
  TriggerDecision decision = TriggerDecision::kWait;
  int64_t trigger_seq = -1;
  int64_t trigger_t_ns = 0;
};

class TriggerMatcher {
 public:
  explicit TriggerMatcher(const TriggerMatcherOptions& options);

  // Pulses in sequence order; a repeated or older seq is ignored (returns false).
  bool add_trigger(int64_t seq, int64_t t_ns);
  // The frame's pulse; kWait: ask again later (with the longer wait); kNoTrigger and
  // kTimeMismatch: drop the frame (counted).
  TriggerMatch match(uint32_t frame_seq, int64_t buffer_t_ns, int64_t waited_ns);
  void reset();  // the camera re-opened: its sequence restarts
  const TriggerMatchStats& stats() const { return stats_; }

 private:
  bool plausible(int64_t trigger_t_ns, int64_t buffer_t_ns) const {
    return buffer_t_ns >= trigger_t_ns && buffer_t_ns - trigger_t_ns <= options_.max_latency_ns;
  }
  struct Pulse {
    int64_t seq;
    int64_t t_ns;
  };
  void consume_through(int64_t seq);  // drops pulses up to seq (unmatched ones counted)
  const Pulse* only_plausible(int64_t buffer_t_ns) const;  // null: none, or more than one
  TriggerMatch matched(const Pulse& p);                    // p is the frame's pulse
  TriggerMatcherOptions options_;
  std::deque<Pulse> pulses_;
  std::optional<int64_t> offset_;  // trigger seq - frame seq
  int mismatches_in_row_ = 0;
  TriggerMatchStats stats_;
};

}  // namespace hs
