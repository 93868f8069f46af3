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
  EXPECT_EQ(c.mono.initial_median_depth_m, d.mono.initial_median_depth_m);
  EXPECT_EQ(c.mono.max_alignment_window_ns, d.mono.max_alignment_window_ns);
  EXPECT_EQ(c.mono.alignment.max_scale_sigma, d.mono.alignment.max_scale_sigma);
  EXPECT_EQ(c.mono.alignment.accel_bias_prior_sigma, d.mono.alignment.accel_bias_prior_sigma);
  EXPECT_EQ(c.mono.alignment.vision_position_sigma_m, d.mono.alignment.vision_position_sigma_m);
  EXPECT_EQ(c.mono.alignment.vision_rotation_drift_sigma,
            d.mono.alignment.vision_rotation_drift_sigma);
  EXPECT_EQ(c.mono.refine_window_ns, d.mono.refine_window_ns);
  EXPECT_EQ(c.mono.refine_period_ns, d.mono.refine_period_ns);
  EXPECT_EQ(c.mono.refine_max_scale_sigma, d.mono.refine_max_scale_sigma);
  EXPECT_EQ(c.mono.points.min_parallax_deg, d.mono.points.min_parallax_deg);
  EXPECT_EQ(c.mono.init.min_flow_px, d.mono.init.min_flow_px);
}

TEST(TrackerConfig, AMonoRigIsReadAndBadMonoValuesNamed) {
  const test::TempYaml mono(
      "tracker:\n  rig: mono\nmono:\n  refine_window_s: 3.0\n  vision_position_sigma_m: 0.01\n"
      "  vision_rotation_sigma_deg: 0.5\n  rotation_drift_sigma_deg_s: 0.0\n");
  const TrackerOptions o = load_tracker_options(mono.path());
  EXPECT_FALSE(o.stereo);
  EXPECT_EQ(o.mono.refine_window_ns, 3'000'000'000);
  EXPECT_EQ(o.mono.alignment.vision_position_sigma_m, 0.01);
  EXPECT_NEAR(o.mono.alignment.vision_rotation_sigma_rad, 0.5 * M_PI / 180.0, 1e-15);
  EXPECT_EQ(o.mono.alignment.vision_rotation_drift_sigma, 0.0);
  const test::TempYaml bad("mono:\n  initial_median_depth_m: -1.0\n");
  test::expect_input_error([&] { load_tracker_options(bad.path()); }, {bad.path(), "mono"});
  const test::TempYaml short_window("mono:\n  max_alignment_window_s: 0.5\n");
  test::expect_input_error([&] { load_tracker_options(short_window.path()); },
                           {"max_alignment_window_s", "vi_alignment_window_s"});
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
