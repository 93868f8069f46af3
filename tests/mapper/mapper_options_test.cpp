#include "mapper/mapper_options.h"

#include <gtest/gtest.h>

#include "tests/config/config_test_util.h"

namespace hs {
namespace {

using test::expect_input_error;
using test::TempYaml;

TEST(MapperConfig, ShippedFileHoldsTheDefaults) {
  const MapperConfig c = load_mapper_config(HS_SOURCE_DIR "/config/mapper.yaml");
  const MapperOptions d;
  EXPECT_EQ(c.mapper.graph.window_covisible, d.graph.window_covisible);
  EXPECT_EQ(c.mapper.window.pixel_sigma, d.window.pixel_sigma);
  EXPECT_EQ(c.mapper.window.max_imu_gap_ns, d.window.max_imu_gap_ns);
  EXPECT_EQ(c.mapper.graph.max_fixed_keyframes, d.graph.max_fixed_keyframes);
  EXPECT_EQ(c.mapper.ba.function_tolerance, d.ba.function_tolerance);
  EXPECT_EQ(c.mapper.ba.screening_function_tolerance, d.ba.screening_function_tolerance);
  EXPECT_EQ(c.mapper.ba.solver, d.ba.solver);
  EXPECT_NEAR(c.mapper.window_gravity_sigma_rad, d.window_gravity_sigma_rad, 1e-15);
  EXPECT_NEAR(c.mapper.window_gravity_mono_sigma_rad, d.window_gravity_mono_sigma_rad, 1e-15);
  EXPECT_EQ(c.mapper.inertial.every_keyframes, d.inertial.every_keyframes);
  EXPECT_EQ(c.mapper.inertial.max_keyframes, d.inertial.max_keyframes);
  EXPECT_NEAR(c.mapper.inertial.gravity_prior_sigma_rad, d.inertial.gravity_prior_sigma_rad, 1e-15);
  EXPECT_NEAR(c.mapper.inertial.max_tilt_rad, d.inertial.max_tilt_rad, 1e-15);
  EXPECT_EQ(c.mapper.ba.time_budget_ms, d.ba.time_budget_ms);
  EXPECT_EQ(c.mapper.culling.max_imu_span_ns, d.culling.max_imu_span_ns);
  EXPECT_EQ(c.mapper.far_point_disparity_px, d.far_point_disparity_px);
  EXPECT_EQ(c.mapper.new_points.covisible_keyframes, d.new_points.covisible_keyframes);
  EXPECT_EQ(c.mapper.new_points.max_hamming, d.new_points.max_hamming);
  EXPECT_EQ(c.mapper.new_points.min_parallax_deg, d.new_points.min_parallax_deg);
  EXPECT_EQ(c.mapper.window.detected_pixel_sigma, d.window.detected_pixel_sigma);
  EXPECT_EQ(c.mapper.loop.enabled, d.loop.enabled);
  EXPECT_EQ(c.mapper.loop.index.tables, d.loop.index.tables);
  EXPECT_EQ(c.mapper.loop.candidates, d.loop.candidates);
  EXPECT_EQ(c.mapper.loop.verify.min_inliers, d.loop.verify.min_inliers);
  EXPECT_EQ(c.mapper.loop.drift_per_m, d.loop.drift_per_m);
  EXPECT_NEAR(c.mapper.loop.drift_base_rad, d.loop.drift_base_rad, 1e-15);
  EXPECT_NEAR(c.mapper.loop.max_tilt_rad, d.loop.max_tilt_rad, 1e-15);
  EXPECT_EQ(c.mapper.loop.consistent, d.loop.consistent);
  EXPECT_EQ(c.mapper.loop_closing.enabled, d.loop_closing.enabled);
  EXPECT_EQ(c.mapper.loop_closing.min_correction_m, d.loop_closing.min_correction_m);
  EXPECT_NEAR(c.mapper.loop_closing.min_correction_rad, d.loop_closing.min_correction_rad, 1e-15);
  EXPECT_EQ(c.mapper.loop_closing.min_keyframes_between, d.loop_closing.min_keyframes_between);
  EXPECT_EQ(c.mapper.loop_closing.strong_covisibility, d.loop_closing.strong_covisibility);
  EXPECT_EQ(c.mapper.loop_closing.pose_graph.four_dof, d.loop_closing.pose_graph.four_dof);
  EXPECT_EQ(c.mapper.loop_correction_point_keyframes, d.loop_correction_point_keyframes);
  EXPECT_EQ(c.mapper.fuse_revisits, d.fuse_revisits);
  EXPECT_EQ(c.mapper.fusion.max_hamming, d.fusion.max_hamming);
  EXPECT_EQ(c.mapper.fusion.ratio, d.fusion.ratio);
  EXPECT_EQ(c.mapper.fusion.radius_px, d.fusion.radius_px);
  EXPECT_EQ(c.mapper.fusion.max_depth_error, d.fusion.max_depth_error);
  EXPECT_EQ(c.mapper.fusion.revisited_keyframes, d.fusion.revisited_keyframes);
  EXPECT_EQ(c.mapper.fusion.neighbourhood_keyframes, d.fusion.neighbourhood_keyframes);
  EXPECT_EQ(c.mapper.localisation_only, d.localisation_only);
  EXPECT_EQ(c.mapper.full_ba.enabled, d.full_ba.enabled);
  EXPECT_EQ(c.mapper.full_ba.background, d.full_ba.background);
  EXPECT_EQ(c.mapper.full_ba.every_keyframes, d.full_ba.every_keyframes);
  EXPECT_EQ(c.mapper.full_ba.iterations_per_round, d.full_ba.iterations_per_round);
  EXPECT_EQ(c.mapper.full_ba.time_budget_ms, d.full_ba.time_budget_ms);
  EXPECT_EQ(c.mapper.full_ba.far_point_disparity_px, d.full_ba.far_point_disparity_px);
  EXPECT_EQ(c.mapper.loop.merge_worlds, d.loop.merge_worlds);
  EXPECT_EQ(c.mapper.loop.merge_in_run_m, d.loop.merge_in_run_m);
  EXPECT_NEAR(c.mapper.loop.merge_in_run_rad, d.loop.merge_in_run_rad, 1e-15);
  EXPECT_EQ(c.calib.cam0.intrinsics.fx, euroc_stereo_calib().cam0.intrinsics.fx);
}

// The open-loop baseline tools/seed_sweep.sh measures loop closing against: only loops and fusion
// off, everything else as shipped.
TEST(MapperConfig, NoLoopsFileTurnsOffOnlyLoopsAndFusion) {
  const MapperConfig c = load_mapper_config(HS_SOURCE_DIR "/config/mapper_no_loops.yaml");
  const MapperConfig shipped = load_mapper_config(HS_SOURCE_DIR "/config/mapper.yaml");
  EXPECT_FALSE(c.mapper.loop.enabled);
  EXPECT_FALSE(c.mapper.fuse_revisits);
  EXPECT_TRUE(shipped.mapper.loop.enabled);
  EXPECT_TRUE(shipped.mapper.fuse_revisits);
  EXPECT_EQ(c.mapper.window.detected_pixel_sigma, shipped.mapper.window.detected_pixel_sigma);
  EXPECT_EQ(c.mapper.inertial.every_keyframes, shipped.mapper.inertial.every_keyframes);
}

TEST(MapperConfig, ValuesAreReadAndBadOnesNamed) {
  const TempYaml ok(
      "mapper:\n  pixel_sigma: 0.5\ninertial:\n  every_keyframes: 0\nlocal_ba:\n"
      "  time_budget_ms: 40\nculling:\n  max_imu_span_s: 0.25\n");
  const MapperConfig c = load_mapper_config(ok.path());
  EXPECT_EQ(c.mapper.window.pixel_sigma, 0.5);
  EXPECT_EQ(c.mapper.inertial.every_keyframes, 0);
  EXPECT_EQ(c.mapper.ba.time_budget_ms, 40.0);
  EXPECT_EQ(c.mapper.culling.max_imu_span_ns, 250'000'000);

  const TempYaml unknown("mapper:\n  pixel_sigm: 0.5\n");
  expect_input_error([&] { load_mapper_config(unknown.path()); }, {"pixel_sigm", "pixel_sigma"});
  const TempYaml solver("local_ba:\n  solver: ceres\n");
  EXPECT_EQ(load_mapper_config(solver.path()).mapper.ba.solver, LocalBaOptions::Solver::kCeres);
  const TempYaml bad_solver("local_ba:\n  solver: gauss\n");
  expect_input_error([&] { load_mapper_config(bad_solver.path()); },
                     {"local_ba.solver", "ceres or schur_lm", "gauss"});
  const TempYaml far("mapper:\n  far_point_disparity_px: 0\n");
  EXPECT_EQ(load_mapper_config(far.path()).mapper.far_point_disparity_px, 0.0);
  const TempYaml negative("mapper:\n  pixel_sigma: -1\n");
  expect_input_error([&] { load_mapper_config(negative.path()); }, {"pixel_sigma", ":2"});
  const TempYaml new_points(
      "mapper:\n  octave_scale: 1.5\nnew_points:\n  covisible_keyframes: 5\n  max_hamming: 40\n"
      "  min_parallax_deg: 2\n  pixel_sigma: 0.8\n");
  const MapperConfig n = load_mapper_config(new_points.path());
  EXPECT_EQ(n.mapper.new_points.covisible_keyframes, 5u);
  EXPECT_EQ(n.mapper.new_points.max_hamming, 40);
  EXPECT_EQ(n.mapper.new_points.min_parallax_deg, 2.0);
  EXPECT_EQ(n.mapper.new_points.octave_scale, 1.5) << "the pyramid's, from the mapper section";
  EXPECT_EQ(n.mapper.window.detected_pixel_sigma, 0.8);
  const TempYaml bad_ratio("new_points:\n  ratio: 1.5\n");
  expect_input_error([&] { load_mapper_config(bad_ratio.path()); }, {"new_points", "range"});
  const TempYaml loop("loop:\n  enabled: false\n  candidates: 5\n  drift_per_m: 0.01\n");
  const MapperConfig l = load_mapper_config(loop.path());
  EXPECT_FALSE(l.mapper.loop.enabled);
  EXPECT_EQ(l.mapper.loop.candidates, 5u);
  EXPECT_EQ(l.mapper.loop.drift_per_m, 0.01);
  const TempYaml bad_loop("loop:\n  min_inliers: 3\n");
  expect_input_error([&] { load_mapper_config(bad_loop.path()); }, {"loop", "range"});
  const TempYaml closing("loop_closing:\n  four_dof: false\n  min_correction_m: 0.1\n");
  EXPECT_FALSE(load_mapper_config(closing.path()).mapper.loop_closing.pose_graph.four_dof);
  EXPECT_EQ(load_mapper_config(closing.path()).mapper.loop_closing.min_correction_m, 0.1);
  const TempYaml bad_closing("loop_closing:\n  loop_weight: 0\n");
  expect_input_error([&] { load_mapper_config(bad_closing.path()); }, {"loop_closing", "range"});
  const TempYaml fusion(
      "fusion:\n  enabled: false\n  radius_px: 2.5\nlocalisation:\n  only: true\n");
  EXPECT_FALSE(load_mapper_config(fusion.path()).mapper.fuse_revisits);
  EXPECT_EQ(load_mapper_config(fusion.path()).mapper.fusion.radius_px, 2.5);
  EXPECT_TRUE(load_mapper_config(fusion.path()).mapper.localisation_only);
  const TempYaml bad_fusion("fusion:\n  revisited_keyframes: 0\n");
  expect_input_error([&] { load_mapper_config(bad_fusion.path()); }, {"fusion", "range"});
  const TempYaml full_ba(
      "full_ba:\n  background: false\n  every_keyframes: 40\n  iterations_per_round: 3\n");
  EXPECT_FALSE(load_mapper_config(full_ba.path()).mapper.full_ba.background);
  EXPECT_EQ(load_mapper_config(full_ba.path()).mapper.full_ba.every_keyframes, 40);
  EXPECT_EQ(load_mapper_config(full_ba.path()).mapper.full_ba.iterations_per_round, 3);
  const TempYaml bad_full_ba("full_ba:\n  time_budget_ms: 0\n");
  expect_input_error([&] { load_mapper_config(bad_full_ba.path()); }, {"full_ba", "range"});
  const TempYaml bad_every("full_ba:\n  every_keyframes: -5\n");
  expect_input_error([&] { load_mapper_config(bad_every.path()); }, {"full_ba", "range"});
  const TempYaml bad_calib("calibration:\n  imu: missing_imu.yaml\n");
  expect_input_error([&] { load_mapper_config(bad_calib.path()); }, {"missing_imu.yaml"});
}

}  // namespace
}  // namespace hs
