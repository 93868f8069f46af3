#include "tracker/tracker_options.h"

#include <gtest/gtest.h>

#include "tests/config/config_test_util.h"

namespace hs {
namespace {

TEST(TrackerConfig, ShippedFileHoldsTheDefaults) {
  const TrackerOptions c = load_tracker_options(HS_SOURCE_DIR "/config/euroc.yaml");
  const TrackerOptions d;
  EXPECT_EQ(c.threads, d.threads);
  EXPECT_EQ(c.max_points_per_frame, d.max_points_per_frame);
  EXPECT_EQ(c.orb.num_features, d.orb.num_features);
  EXPECT_EQ(c.orb.num_levels, d.orb.num_levels);
  EXPECT_EQ(c.direct.sparse.finest_level, d.direct.sparse.finest_level);
  EXPECT_EQ(c.keyframe.min_tracked, d.keyframe.min_tracked);
  EXPECT_EQ(c.prior_fading, d.prior_fading);
}

TEST(TrackerConfig, ThreadsAreReadAndANegativeCountNamed) {
  const test::TempYaml two("tracker:\n  threads: 2\n");
  EXPECT_EQ(load_tracker_options(two.path()).threads, 2);
  const test::TempYaml negative("tracker:\n  threads: -1\n");
  test::expect_input_error([&] { load_tracker_options(negative.path()); },
                           {negative.path() + ":2", "threads"});
}

}  // namespace
}  // namespace hs
