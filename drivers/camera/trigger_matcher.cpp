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

const TriggerMatcher::Pulse* TriggerMatcher::only_plausible(int64_t buffer_t_ns) const {
  const Pulse* found = nullptr;
  for (const Pulse& p : pulses_) {
    if (!plausible(p.t_ns, buffer_t_ns)) continue;
    if (found) return nullptr;
    found = &p;
  }
  return found;
}

TriggerMatch TriggerMatcher::matched(const Pulse& p) {
  TriggerMatch m{TriggerDecision::kMatched, p.seq, p.t_ns};
  mismatches_in_row_ = 0;
  consume_through(p.seq);  // p is gone after this
  ++stats_.matched;
  return m;
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
      if (const Pulse* only = only_plausible(buffer_t_ns)) {
        // The pairing slipped (a pulse the camera never saw) and the buffer time names its pulse
        // unambiguously: follow it at once instead of dropping relock_after frames.
        offset_ = only->seq - static_cast<int64_t>(frame_seq);
        ++stats_.relocks;
        return matched(*only);
      }
      if (may_wait && buffer_t_ns > pulses_.back().t_ns) {
        // A pulse not heard yet may be this frame's (the camera missed the one wanted and its
        // next TRIGGER message is still on its way): wait for it before calling a mismatch.
        m.decision = TriggerDecision::kWait;
        return m;
      }
      ++stats_.time_mismatches;
      m.decision = TriggerDecision::kTimeMismatch;
      if (++mismatches_in_row_ >= options_.relock_after) {
        offset_.reset();  // the pairing slipped (a pulse the camera never saw): learn it anew
        mismatches_in_row_ = 0;
        ++stats_.relocks;
      }
      return m;
    }
    return matched(p);
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
