#include "drivers/camera/trigger_matcher.h"

namespace hs {

TriggerMatcher::TriggerMatcher(const TriggerMatcherOptions& options) : options_(options) {}

bool TriggerMatcher::add_trigger(int64_t seq, int64_t t_ns) {
  if (!pulses_.empty() && seq <= pulses_.back().seq) return false;
  pulses_.push_back({seq, t_ns});
  while (pulses_.size() > options_.max_triggers) {
    pulses_.pop_front();
    ++stats_.triggers_without_frame;
  }
  return true;
}

void TriggerMatcher::consume_through(int64_t seq) {
  while (!pulses_.empty() && pulses_.front().seq <= seq) {
    if (pulses_.front().seq < seq) ++stats_.triggers_without_frame;
    pulses_.pop_front();
  }
}

void TriggerMatcher::reset() {
  offset_.reset();
  mismatches_in_row_ = 0;
}

TriggerMatch TriggerMatcher::match(uint32_t frame_seq, int64_t buffer_t_ns, int64_t waited_ns) {
  TriggerMatch m;
  const bool may_wait = waited_ns < options_.max_wait_ns;
  if (!offset_) {
    // Learn the offset: the newest pulse the buffer time plausibly follows.
    const Pulse* best = nullptr;
    for (const Pulse& p : pulses_)
      if (plausible(p.t_ns, buffer_t_ns)) best = &p;
    if (!best) {
      m.decision = may_wait ? TriggerDecision::kWait : TriggerDecision::kNoTrigger;
      if (!may_wait) ++stats_.frames_without_trigger;
      return m;
    }
    offset_ = best->seq - static_cast<int64_t>(frame_seq);
  }
  const int64_t want = static_cast<int64_t>(frame_seq) + *offset_;
  for (const Pulse& p : pulses_) {
    if (p.seq != want) continue;
    m.trigger_seq = p.seq;
    m.trigger_t_ns = p.t_ns;
    if (!plausible(p.t_ns, buffer_t_ns)) {
      ++stats_.time_mismatches;
      m.decision = TriggerDecision::kTimeMismatch;
      if (++mismatches_in_row_ >= options_.relock_after) {
        offset_.reset();  // the pairing slipped (a pulse the camera never saw): learn it anew
        mismatches_in_row_ = 0;
        ++stats_.relocks;
      }
      return m;
    }
    mismatches_in_row_ = 0;
    consume_through(p.seq);
    ++stats_.matched;
    m.decision = TriggerDecision::kMatched;
    return m;
  }
  // No pulse with that seq: lost (newer pulses exist) or not heard yet.
  const bool newer = !pulses_.empty() && pulses_.back().seq > want;
  if (newer || !may_wait) {
    ++stats_.frames_without_trigger;
    m.decision = TriggerDecision::kNoTrigger;
    return m;
  }
  m.decision = TriggerDecision::kWait;
  return m;
}

}  // namespace hs
