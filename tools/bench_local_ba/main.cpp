// hs-bench-local-ba: time per local visual-inertial bundle adjustment (mapper/local_ba.h) on a
// window of 10 keyframes at 3 Hz, each seeing 150 points in both cameras (about 300 reprojection
// terms per keyframe), IMU factors between consecutive keyframes, the oldest keyframe fixed.
// Synthetic scenes as in the unit tests: 1 px noise, a share of gross outliers, initial guess
// off by 5 cm / 2 deg (points 5 cm, velocities 0.1 m/s, biases unknown). Prints the wall time
// and this thread's CPU time (other processes on the shared cores do not inflate the latter).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <random>
#include <vector>

#include "common/core/monotonic_clock.h"
#include "mapper/local_ba.h"
#include "tests/mapper/local_ba_test_scene.h"

namespace {

// Value at quantile q (0..1) of `values` (reordered).
double quantile(std::vector<double> values, double q) {
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(q * values.size()));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Time per local visual-inertial bundle adjustment (10 keyframes, stereo + IMU)."};
  int runs = 50;
  int keyframes = 10;
  int points = 150;
  double outliers = 0.02;
  app.add_option("--runs", runs, "random windows")->check(CLI::PositiveNumber);
  app.add_option("--keyframes", keyframes, "keyframes per window")->check(CLI::Range(2, 100));
  app.add_option("--points", points, "points seen per keyframe (both cameras)")
      ->check(CLI::Range(10, 1000));
  app.add_option("--outliers", outliers, "share of gross outliers")->check(CLI::Range(0.0, 0.5));
  CLI11_PARSE(app, argc, argv);

  const hs::StereoCalib calib = hs::euroc_stereo_calib();
  hs::LocalBaOptions options;
  options.time_budget_ms = 1e6;  // measure the full optimisation
  const hs::LocalBundleAdjuster ba(calib, options);
  hs::test::BaSceneOptions scene_options;
  scene_options.num_keyframes = keyframes;
  scene_options.max_points_per_keyframe = points;
  scene_options.points_per_keyframe = std::max(60, points / 2);
  scene_options.outlier_fraction = outliers;

  std::vector<double> wall_ms, cpu_ms, translation_cm, rotation_deg;
  double observations = 0.0, iterations = 0.0;
  for (int run = 0; run < runs; ++run) {
    std::mt19937 rng(static_cast<unsigned>(run + 1));
    hs::test::BaScene scene = hs::test::make_ba_scene(calib, scene_options, &rng);
    scene.input.keyframes.front().fixed = true;
    const std::vector<hs::BaKeyframe> truth = scene.input.keyframes;
    hs::test::perturb(&scene.input, 0.05, 2.0 * EIGEN_PI / 180.0, 0.1, 0.05, &rng);

    const double cpu_start = 1e3 * hs::thread_cpu_s();
    const hs::LocalBaResult result = ba.optimise(scene.input);
    cpu_ms.push_back(1e3 * hs::thread_cpu_s() - cpu_start);
    wall_ms.push_back(result.stats.time_ms);
    observations += static_cast<double>(scene.input.observations.size()) / runs;
    iterations += static_cast<double>(result.stats.iterations) / runs;
    double max_t = 0.0, max_r = 0.0;
    for (size_t k = 0; k < truth.size(); ++k) {
      const hs::NavState& a = result.keyframes[k].state;
      max_t = std::max(max_t, (a.p_w_b - truth[k].state.p_w_b).norm());
      max_r = std::max(max_r, hs::test::rotation_error_rad(a.q_w_b, truth[k].state.q_w_b));
    }
    translation_cm.push_back(100.0 * max_t);
    rotation_deg.push_back(max_r * 180.0 / EIGEN_PI);
  }
  std::printf("local BA: %d windows of %d keyframes, %.0f reprojection terms + %d IMU factors\n",
              runs, keyframes, observations, keyframes - 1);
  std::printf("  wall ms     median %7.2f  p95 %7.2f  max %7.2f\n", quantile(wall_ms, 0.5),
              quantile(wall_ms, 0.95), quantile(wall_ms, 1.0));
  std::printf("  cpu ms      median %7.2f  p95 %7.2f  max %7.2f\n", quantile(cpu_ms, 0.5),
              quantile(cpu_ms, 0.95), quantile(cpu_ms, 1.0));
  std::printf("  iterations  mean %.1f (both rounds)\n", iterations);
  std::printf(
      "  worst keyframe error per window: translation cm median %.3f p95 %.3f, "
      "rotation deg median %.4f p95 %.4f\n",
      quantile(translation_cm, 0.5), quantile(translation_cm, 0.95), quantile(rotation_deg, 0.5),
      quantile(rotation_deg, 0.95));
  return 0;
}
