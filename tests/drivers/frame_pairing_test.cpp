// Drop detection, stereo pairing and trigger matching: the camera driver's bookkeeping.
#include <gtest/gtest.h>

#include "drivers/camera/sequence_tracker.h"
#include "drivers/camera/stereo_pairer.h"
#include "drivers/camera/trigger_matcher.h"

namespace hs {
namespace {

constexpr int64_t kMs = 1'000'000;

TEST(SequenceTracker, GapsAreDroppedFramesAndRepeatsAreFlagged) {
  SequenceTracker t;
  EXPECT_EQ(t.add(10), 0);
  EXPECT_EQ(t.add(11), 0);
  EXPECT_EQ(t.add(14), 2);
  EXPECT_EQ(t.add(14), -1);
  EXPECT_EQ(t.add(13), -1);
  EXPECT_EQ(t.stats().dropped, 2);
  EXPECT_EQ(t.stats().backwards, 2);
  t.reset();  // re-opened: starts again at 0
  EXPECT_EQ(t.add(0), 0);
  EXPECT_EQ(t.stats().frames, 4);
}

TEST(StereoPairer, PairsByTimeAndDropsFramesTheOtherSideLost) {
  StereoPairer p(2 * kMs);
  std::vector<SideFrame> dropped;
  std::vector<std::pair<SideFrame, SideFrame>> pairs;
  auto add = [&](int side, uint32_t seq, int64_t t_ms) {
    for (auto& pr : p.add(side, {seq, t_ms * kMs, seq}, &dropped)) pairs.push_back(pr);
  };
  add(0, 0, 100);
  add(1, 5, 101);  // the right device started 5 frames earlier
  add(0, 1, 150);
  add(0, 2, 200);  // right lost its frame at 150
  add(1, 7, 200);
  add(1, 8, 250);
  add(0, 3, 250);
  ASSERT_EQ(pairs.size(), 3u);
  EXPECT_EQ(pairs[0].first.seq, 0u);
  EXPECT_EQ(pairs[0].second.seq, 5u);
  EXPECT_EQ(pairs[1].first.seq, 2u);
  EXPECT_EQ(pairs[1].second.seq, 7u);
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_EQ(dropped[0].seq, 1u);
  EXPECT_EQ(p.stats().unpaired_left, 1);
  EXPECT_EQ(p.stats().sequence_offset_changes, 0);
}

TEST(StereoPairer, ASilentSideDoesNotHoardFrames) {
  StereoPairer p(2 * kMs, 3);
  std::vector<SideFrame> dropped;
  for (uint32_t i = 0; i < 10; ++i) EXPECT_TRUE(p.add(0, {i, i * 50 * kMs, i}, &dropped).empty());
  EXPECT_EQ(dropped.size(), 7u);
  EXPECT_EQ(p.stats().unpaired_left, 7);
}

TEST(TriggerMatcher, LearnsTheOffsetAndMatchesBySequenceWithATimeCheck) {
  TriggerMatcher m(TriggerMatcherOptions{});
  for (int64_t s = 40; s < 50; ++s) m.add_trigger(s, s * 50 * kMs);
  // Frame 0's buffer is stamped 12 ms after pulse 42.
  TriggerMatch r = m.match(0, 42 * 50 * kMs + 12 * kMs, 0);
  ASSERT_EQ(r.decision, TriggerDecision::kMatched);
  EXPECT_EQ(r.trigger_seq, 42);
  r = m.match(1, 43 * 50 * kMs + 11 * kMs, 0);
  EXPECT_EQ(r.trigger_seq, 43);
  // A buffer stamped 45 ms after pulse 44, more than max_latency: not that pulse's frame, and it
  // fits no other.
  r = m.match(2, 44 * 50 * kMs + 45 * kMs, 0);
  EXPECT_EQ(r.decision, TriggerDecision::kTimeMismatch);
  EXPECT_EQ(m.stats().time_mismatches, 1);
  EXPECT_EQ(m.stats().matched, 2);
  EXPECT_EQ(m.stats().relocks, 0);
}

TEST(TriggerMatcher, FramesWaitForLateTriggersAndGiveUpOnLostOnes) {
  TriggerMatcherOptions o;
  o.max_wait_ns = 100 * kMs;
  TriggerMatcher m(o);
  m.add_trigger(0, 1000 * kMs);
  EXPECT_EQ(m.match(0, 1010 * kMs, 0).decision, TriggerDecision::kMatched);
  // Frame 1's TRIGGER has not arrived yet: wait.
  EXPECT_EQ(m.match(1, 1060 * kMs, 5 * kMs).decision, TriggerDecision::kWait);
  m.add_trigger(1, 1050 * kMs);
  EXPECT_EQ(m.match(1, 1060 * kMs, 20 * kMs).decision, TriggerDecision::kMatched);
  // Pulse 2's message was lost; pulse 3 came: frame 2 has no trigger.
  m.add_trigger(3, 1150 * kMs);
  EXPECT_EQ(m.match(2, 1110 * kMs, 0).decision, TriggerDecision::kNoTrigger);
  // Frame 4 never gets its pulse: it waits, then gives up.
  EXPECT_EQ(m.match(4, 1210 * kMs, 50 * kMs).decision, TriggerDecision::kWait);
  EXPECT_EQ(m.match(4, 1210 * kMs, 150 * kMs).decision, TriggerDecision::kNoTrigger);
  EXPECT_EQ(m.stats().frames_without_trigger, 2);
  EXPECT_FALSE(m.add_trigger(3, 1150 * kMs)) << "a repeated pulse is ignored";
}

TEST(TriggerMatcher, APulseTheCameraNeverSawRelocksAtOnceWhenTheTimeNamesTheNext) {
  TriggerMatcher m(TriggerMatcherOptions{});
  for (int64_t s = 0; s < 20; ++s) m.add_trigger(s, s * 50 * kMs);
  EXPECT_EQ(m.match(0, 0 * 50 * kMs + 10 * kMs, 0).trigger_seq, 0);
  EXPECT_EQ(m.match(1, 1 * 50 * kMs + 10 * kMs, 0).trigger_seq, 1);
  // The camera missed pulse 2: frame 2 comes from pulse 3, the only pulse its time fits.
  TriggerMatch r = m.match(2, 3 * 50 * kMs + 10 * kMs, 0);
  EXPECT_EQ(r.decision, TriggerDecision::kMatched);
  EXPECT_EQ(r.trigger_seq, 3);
  EXPECT_EQ(r.trigger_t_ns, 3 * 50 * kMs);
  r = m.match(3, 4 * 50 * kMs + 10 * kMs, 0);
  EXPECT_EQ(r.trigger_seq, 4);
  EXPECT_EQ(m.stats().matched, 4);
  EXPECT_EQ(m.stats().relocks, 1);
  EXPECT_EQ(m.stats().time_mismatches, 0);
  EXPECT_EQ(m.stats().triggers_without_frame, 1);  // pulse 2
}

TEST(TriggerMatcher, AFrameAfterAMissedPulseWaitsForTheTriggerMessageItFollows) {
  TriggerMatcher m(TriggerMatcherOptions{});
  for (int64_t s = 0; s < 3; ++s) m.add_trigger(s, s * 50 * kMs);
  EXPECT_EQ(m.match(0, 1 * 50 * kMs + 10 * kMs, 0).trigger_seq, 1);
  // The camera missed pulse 2; frame 1 comes from pulse 3, whose message has not arrived yet.
  const int64_t frame_t = 3 * 50 * kMs + 10 * kMs;
  EXPECT_EQ(m.match(1, frame_t, 5 * kMs).decision, TriggerDecision::kWait);
  m.add_trigger(3, 3 * 50 * kMs);
  const TriggerMatch r = m.match(1, frame_t, 20 * kMs);
  EXPECT_EQ(r.decision, TriggerDecision::kMatched);
  EXPECT_EQ(r.trigger_seq, 3);
  // A frame no pulse explains, once the wait is over, is a mismatch.
  m.add_trigger(4, 4 * 50 * kMs);
  EXPECT_EQ(m.match(2, 5 * 50 * kMs + 45 * kMs, 5 * kMs).decision, TriggerDecision::kWait);
  EXPECT_EQ(m.match(2, 5 * 50 * kMs + 45 * kMs, 150 * kMs).decision,
            TriggerDecision::kTimeMismatch);
  EXPECT_EQ(m.stats().time_mismatches, 1);
  EXPECT_EQ(m.stats().relocks, 1);
}

TEST(TriggerMatcher, AmbiguousTimesRelockOnlyAfterMismatchesInARow) {
  // 30 Hz pulses with a 40 ms latency window: a buffer can fit two pulses.
  TriggerMatcherOptions o;
  o.relock_after = 2;
  TriggerMatcher m(o);
  auto pulse_t = [](int64_t s) { return s * 33 * kMs; };
  for (int64_t s = 0; s < 20; ++s) m.add_trigger(s, pulse_t(s));
  EXPECT_EQ(m.match(0, pulse_t(0) + 10 * kMs, 0).trigger_seq, 0);
  // From here the camera skipped a pulse: frame k is exposed by pulse k + 1, stamped 35 ms after
  // it, which also fits pulse k + 2.
  EXPECT_EQ(m.match(1, pulse_t(2) + 35 * kMs, 0).decision, TriggerDecision::kTimeMismatch);
  EXPECT_EQ(m.match(2, pulse_t(3) + 35 * kMs, 0).decision, TriggerDecision::kTimeMismatch);
  EXPECT_EQ(m.stats().relocks, 1);
  // Learnt anew from the newest pulse the buffer follows.
  const TriggerMatch r = m.match(3, pulse_t(4) + 10 * kMs, 0);
  EXPECT_EQ(r.decision, TriggerDecision::kMatched);
  EXPECT_EQ(r.trigger_seq, 4);
  EXPECT_EQ(m.stats().triggers_without_frame, 3);  // pulses 1, 2, 3 exposed no frame we kept
}

}  // namespace
}  // namespace hs
