#include "mapper/local_ba.h"

#include <chrono>

#include "common/core/monotonic_clock.h"
#include "mapper/local_ba_problem.h"

namespace hs {

LocalBundleAdjuster::LocalBundleAdjuster(const StereoCalib& calib, const LocalBaOptions& options)
    : calib_(calib), options_(options) {}

LocalBaResult LocalBundleAdjuster::optimise(const LocalBaInput& input) const {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  const double cpu_start_s = thread_cpu_s();
  const auto elapsed_ms = [&] {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  };
  const LocalBaIndex index = resolve_local_ba_input(input);
  LocalBaProblem problem(calib_, options_, input, index);

  LocalBaResult result;
  const int num_rounds = options_.reject_outliers ? 2 : 1;
  // The budget is of this thread's CPU time: a busy host delays the result but does not cut its
  // iterations, so what the mapper sends does not depend on the other load on the cores.
  const double cpu_deadline_s = cpu_start_s + 1e-3 * options_.time_budget_ms;
  for (int round = 0; round < num_rounds; ++round) {
    if (thread_cpu_s() >= cpu_deadline_s) break;
    if (round > 0) problem.drop_outliers(options_.chi2_threshold);
    if (!problem.has_terms()) break;
    const bool screening = round + 1 < num_rounds;
    const SchurLmSummary summary =
        problem.solve(cpu_deadline_s, screening ? options_.screening_function_tolerance
                                                : options_.function_tolerance);
    if (round == 0) result.stats.initial_cost = summary.initial_cost;
    result.stats.final_cost = summary.final_cost;
    result.stats.iterations += summary.successful_steps + summary.unsuccessful_steps;
    ++result.stats.rounds;
  }

  problem.estimate(&result.keyframes, &result.points, &result.g_w);
  result.outliers.resize(input.observations.size());
  for (size_t k = 0; k < result.outliers.size(); ++k) {
    result.outliers[k] = !(problem.chi2(k) <= options_.chi2_threshold);
    result.stats.num_outliers += result.outliers[k];
  }
  result.stats.time_ms = elapsed_ms();
  result.stats.cpu_ms = 1e3 * (thread_cpu_s() - cpu_start_s);
  return result;
}

}  // namespace hs
