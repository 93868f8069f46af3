// hs-bench-local-ba: time per local visual-inertial bundle adjustment (mapper/local_ba.h) on a
// window of 10 keyframes at 3 Hz, each seeing 150 points in both cameras (about 300 reprojection
// terms per keyframe), IMU factors between consecutive keyframes, the oldest keyframe fixed.
// Synthetic scenes as in the unit tests: 1 px noise, a share of gross outliers, initial guess
// off by 5 cm / 2 deg (points 5 cm, velocities 0.1 m/s, biases unknown). Prints the wall time
// and this thread's CPU time (other processes on the shared cores do not inflate the latter),
// for Ceres' solver and mapper/schur_lm.h on the same windows.
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
  hs::test::BaSceneOptions scene_options;
  scene_options.num_keyframes = keyframes;
  scene_options.max_points_per_keyframe = points;
  scene_options.points_per_keyframe = std::max(60, points / 2);
  scene_options.outlier_fraction = outliers;

  // Both solvers on every window, one after the other: the host's load changes by the second
  // here, so only figures of the same run compare.
  struct Solver {
    const char* name;
    hs::LocalBundleAdjuster ba;
    std::vector<double> wall_ms, cpu_ms, translation_cm, rotation_deg;
    double iterations = 0.0;
  };
  std::vector<Solver> solvers;
  for (const auto& [name, solver] : {std::pair("ceres", hs::LocalBaOptions::Solver::kCeres),
                                     std::pair("schur_lm", hs::LocalBaOptions::Solver::kSchurLm)}) {
    options.solver = solver;
    solvers.push_back(Solver{name, hs::LocalBundleAdjuster(calib, options), {}, {}, {}, {}});
  }
  double observations = 0.0;
  for (int run = 0; run < runs; ++run) {
    std::mt19937 rng(static_cast<unsigned>(run + 1));
    hs::test::BaScene scene = hs::test::make_ba_scene(calib, scene_options, &rng);
    scene.input.keyframes.front().fixed = true;
    const std::vector<hs::BaKeyframe> truth = scene.input.keyframes;
    hs::test::perturb(&scene.input, 0.05, 2.0 * EIGEN_PI / 180.0, 0.1, 0.05, &rng);
    observations += static_cast<double>(scene.input.observations.size()) / runs;
    for (Solver& s : solvers) {
      const double cpu_start = 1e3 * hs::thread_cpu_s();
      const hs::LocalBaResult result = s.ba.optimise(scene.input);
      s.cpu_ms.push_back(1e3 * hs::thread_cpu_s() - cpu_start);
      s.wall_ms.push_back(result.stats.time_ms);
      s.iterations += static_cast<double>(result.stats.iterations) / runs;
      double max_t = 0.0, max_r = 0.0;
      for (size_t k = 0; k < truth.size(); ++k) {
        const hs::NavState& a = result.keyframes[k].state;
        max_t = std::max(max_t, (a.p_w_b - truth[k].state.p_w_b).norm());
        max_r = std::max(max_r, hs::test::rotation_error_rad(a.q_w_b, truth[k].state.q_w_b));
      }
      s.translation_cm.push_back(100.0 * max_t);
      s.rotation_deg.push_back(max_r * 180.0 / EIGEN_PI);
    }
  }
  std::printf("local BA: %d windows of %d keyframes, %.0f reprojection terms + %d IMU factors\n",
              runs, keyframes, observations, keyframes - 1);
  for (Solver& s : solvers) {
    std::printf("solver %s\n", s.name);
    std::printf("  wall ms     median %7.2f  p95 %7.2f  max %7.2f\n", quantile(s.wall_ms, 0.5),
                quantile(s.wall_ms, 0.95), quantile(s.wall_ms, 1.0));
    std::printf("  cpu ms      median %7.2f  p95 %7.2f  max %7.2f\n", quantile(s.cpu_ms, 0.5),
                quantile(s.cpu_ms, 0.95), quantile(s.cpu_ms, 1.0));
    std::printf("  iterations  mean %.1f (both rounds)\n", s.iterations);
    std::printf(
        "  worst keyframe error per window: translation cm median %.3f p95 %.3f, "
        "rotation deg median %.4f p95 %.4f\n",
        quantile(s.translation_cm, 0.5), quantile(s.translation_cm, 0.95),
        quantile(s.rotation_deg, 0.5), quantile(s.rotation_deg, 0.95));
  }
  double ratio_sum = 0.0;
  for (size_t k = 0; k < solvers[0].cpu_ms.size(); ++k)
    ratio_sum += solvers[1].cpu_ms[k] / solvers[0].cpu_ms[k];
  std::printf("schur_lm / ceres CPU time: %.2fx (mean over the windows)\n",
              ratio_sum / static_cast<double>(runs));
  return 0;
}
