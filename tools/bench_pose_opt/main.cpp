// hs-bench-pose-opt: time per motion-only optimisation (tracker/pose_opt.h) on one core, for
// 50/100/200/400 observations, in pose-only and visual-inertial mode (previous state fixed, and
// free under a prior). Synthetic scenes as in the unit tests: EuRoC rig, points 2-15 m away,
// 0.7-1.2 px noise, a share of gross outliers, initial guess off by 5 cm / 1 deg. Times are
// the thread's CPU time, so that other processes on the shared cores do not inflate them.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <vector>

#include "common/core/monotonic_clock.h"
#include "tests/imu/analytic_motion.h"
#include "tests/tracker/pose_opt_test_scene.h"
#include "tracker/pose_opt.h"

namespace {

struct Case {
  std::vector<hs::PoseObservation> observations;
  hs::NavState initial;
};

struct Figures {
  double median_us = 0.0;
  double mean_us = 0.0;
  double iterations = 0.0;
  double valid_share = 0.0;
};

// Times `optimise(case)` over all cases, `repeats` times each.
template <class Optimise>
Figures time_cases(const std::vector<Case>& cases, int repeats, const Optimise& optimise) {
  std::vector<double> us;
  Figures f;
  for (const Case& c : cases) {
    for (int r = 0; r < repeats; ++r) {
      const double start = 1e6 * hs::thread_cpu_s();
      const hs::PoseOptResult result = optimise(c);
      us.push_back(1e6 * hs::thread_cpu_s() - start);
      f.iterations += result.iterations;
      f.valid_share += result.valid();
    }
  }
  const double n = static_cast<double>(us.size());
  for (double t : us) f.mean_us += t / n;
  std::nth_element(us.begin(), us.begin() + us.size() / 2, us.end());
  f.median_us = us[us.size() / 2];
  f.iterations /= n;
  f.valid_share /= n;
  return f;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Time per motion-only optimisation of the tracker."};
  int scenes = 50;
  int repeats = 20;
  double outliers = 0.2;
  app.add_option("--scenes", scenes, "random scenes per size")->check(CLI::PositiveNumber);
  app.add_option("--repeats", repeats, "optimisations per scene")->check(CLI::PositiveNumber);
  app.add_option("--outliers", outliers, "share of gross outliers")->check(CLI::Range(0.0, 0.9));
  CLI11_PARSE(app, argc, argv);

  const hs::StereoCalib calib = hs::euroc_stereo_calib();
  const hs::PoseOptimizer optimizer(calib);
  const hs::test::AnalyticMotion motion;
  const int64_t t0 = 500'000'000, t1 = 550'000'000;  // 20 Hz frames, 200 Hz IMU
  const hs::ImuPreintegration pim =
      hs::preintegrate(motion.samples(0, 1'000'000'000, 5'000'000), t0, t1, hs::ImuBias{});
  hs::PreviousState fixed;
  fixed.state = motion.state(t0);
  hs::PreviousState free = fixed;
  free.fixed = false;
  free.information = 1e6 * hs::Matrix15d::Identity();
  const hs::NavState truth = motion.state(t1);

  std::printf("%d scenes x %d repeats per size, %.0f%% outliers; thread CPU time\n", scenes,
              repeats, 100.0 * outliers);
  std::printf("%-6s %-20s %10s %10s %8s %7s\n", "obs", "mode", "median_us", "mean_us", "iters",
              "valid");
  for (const int n : {50, 100, 200, 400}) {
    std::vector<Case> cases;
    for (int s = 0; s < scenes; ++s) {
      std::mt19937 rng(1000 * n + s);
      hs::test::SceneOptions so;
      so.num_observations = n;
      so.outlier_fraction = outliers;
      cases.push_back({hs::test::make_scene(calib, truth, so, &rng).observations,
                       hs::test::perturbed(truth, 0.05, 1.0 * EIGEN_PI / 180.0, &rng)});
    }
    const struct {
      const char* name;
      const hs::PreviousState* previous;
    } modes[] = {
        {"pose-only", nullptr}, {"inertial/fixed-prev", &fixed}, {"inertial/free-prev", &free}};
    for (const auto& mode : modes) {
      const Figures f = time_cases(cases, repeats, [&](const Case& c) {
        return mode.previous == nullptr
                   ? optimizer.optimise_pose(c.initial, c.observations)
                   : optimizer.optimise_inertial(c.initial, c.observations, pim, *mode.previous);
      });
      std::printf("%-6d %-20s %10.1f %10.1f %8.1f %6.0f%%\n", n, mode.name, f.median_us, f.mean_us,
                  f.iterations, 100.0 * f.valid_share);
    }
  }
  return 0;
}
