#include <gtest/gtest.h>

#include <vector>

#include "drivers/trigger/pulse_schedule.h"
#include "drivers/trigger/trigger_options.h"
#include "tests/config/config_test_util.h"

namespace hs {
namespace {

constexpr int64_t kMs = 1'000'000;

TEST(PulseSchedule, AbsoluteDeadlinesWithoutDrift) {
  PulseSchedule s(1000 * kMs, 30.0);  // a period that is not a whole number of ns
  int64_t last = 0;
  for (int k = 0; k < 3000; ++k) last = s.next(last);
  // Pulse 2999 is at start + 2999 / 30 s exactly (rounded once), not 2999 rounded periods.
  EXPECT_EQ(last, 1000 * kMs + 99'966'666'667);
  EXPECT_EQ(s.skipped(), 0);
}

TEST(PulseSchedule, DeadlinesMissedByAWholePeriodAreSkippedAndCounted) {
  PulseSchedule s(0, 20.0);
  EXPECT_EQ(s.next(0), 0);
  EXPECT_EQ(s.next(10 * kMs), 50 * kMs);    // on time
  EXPECT_EQ(s.next(130 * kMs), 100 * kMs);  // 30 ms late: still pulsed (within its period)
  EXPECT_EQ(s.next(420 * kMs), 400 * kMs);  // 150, 200, 250, 300, 350 are gone
  EXPECT_EQ(s.skipped(), 5);
}

TEST(SyncDivider, EveryNthEdgeFromTheFirstLateOnesCounted) {
  SyncDivider d(3);
  std::vector<bool> due;
  for (int i = 0; i < 7; ++i) due.push_back(d.edges(1));
  EXPECT_EQ(due, (std::vector<bool>{true, false, false, true, false, false, true}));
  // Edges 8 and 9 read together: neither due; 10, 11 and 12: 10 was due, given late.
  EXPECT_FALSE(d.edges(2));
  EXPECT_TRUE(d.edges(3));
  EXPECT_EQ(d.late(), 1);
  EXPECT_TRUE(d.edges(1));   // edge 13
  EXPECT_FALSE(d.edges(1));  // edge 14
  d.restart();               // the line stalled: the next edge is due
  EXPECT_TRUE(d.edges(1));
  EXPECT_TRUE(d.edges(3));  // the newest of three edges is due: on time
  EXPECT_EQ(d.late(), 1);
}

TEST(TriggerOptions, ShippedConfigAndBadValues) {
  const TriggerOptions o = load_trigger_options(HS_SOURCE_DIR "/config/trigger.yaml");
  EXPECT_EQ(o.chip, "gpiochip0");
  EXPECT_EQ(o.rate_hz, 20.0);
  EXPECT_EQ(o.pulse_width_ns, 1 * kMs);
  test::TempYaml wide("trigger:\n  rate_hz: 100\n  pulse_width_s: 0.02\n");
  test::expect_input_error([&] { load_trigger_options(wide.path()); },
                           {wide.path() + ":3", "shorter than a period"});
  EXPECT_EQ(o.sync_line, "");
  EXPECT_EQ(o.sync_divider, 10);
  test::TempYaml divider("trigger:\n  sync_divider: 0\n");
  test::expect_input_error([&] { load_trigger_options(divider.path()); }, {"1 ... 1000"});
  test::TempYaml rate("trigger:\n  rate_hz: 0\n");
  test::expect_input_error([&] { load_trigger_options(rate.path()); }, {"(0, 1000]"});
}

}  // namespace
}  // namespace hs
