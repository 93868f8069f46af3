#pragma once
// Summaries of an offline run: timing statistics (the paper's Table 4 layout) and the
// trajectory evaluation against ground truth.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/eval/evaluate.h"
#include "tracker/offline/offline_run.h"

namespace hs {

struct TimeStats {
  size_t count = 0;
  double total_ms = 0, mean = 0, median = 0, p95 = 0, p99 = 0, max = 0;
};
TimeStats time_stats(std::vector<double> ms);

struct TimingSummary {
  // Per-frame tracking time, ms, of the accepted frames from the one that initialises on.
  TimeStats all, keyframe, non_keyframe;
};

TimingSummary summarise_timing(const OfflineRunResult& result);
std::string timing_text(const TimingSummary& t);

// ATE/RPE of the run's estimate against its ground truth (SE(3) alignment, RPE over 1 m as
// the paper's tables), if it has ground truth.
std::optional<EvalResult> evaluate_run(const OfflineRunResult& result);
// The same for another estimate of the run's frames (e.g. keyframe_relative_estimate).
std::optional<EvalResult> evaluate_run(const OfflineRunResult& result, const Trajectory& est);

// One descriptor mode's figures in the tracker benchmark (one column of the paper's Table 4).
struct ModeReport {
  std::string mode;  // "hybrid" or "every-frame"
  size_t frames = 0;
  int tracked = 0, lost = 0;
  TimingSummary timing;
  std::optional<double> ate_rmse_m;  // hs-eval ATE after SE(3) alignment, with ground truth
  std::string ate_error;             // why there is no ATE, when evaluation failed
  double peak_rss_mb = 0.0;          // of the process that ran this mode alone
  double cpu_s = 0.0;                // user + system CPU time of that process
};

// Everything but the process figures (peak_rss_mb, cpu_s), which the caller measures.
ModeReport mode_report(const std::string& mode, const OfflineRunResult& result);
nlohmann::json to_json(const ModeReport& r);
ModeReport mode_report_from_json(const nlohmann::json& j);  // InputError if malformed

// The targets for hybrid against the every-frame baseline.
struct BenchTargets {
  double hybrid_mean_ms = 5.0;        // per-frame mean
  double non_keyframe_speedup = 3.0;  // every-frame / hybrid, non-keyframe means
  double overall_speedup = 2.0;       // every-frame / hybrid, all-frame means
  double peak_rss_mb = 150.0;         // hybrid
};

struct TargetCheck {
  std::string name;
  std::string value;        // the measured figure, formatted
  std::optional<bool> met;  // nullopt: not measurable (e.g. no ground truth)
};

std::vector<TargetCheck> check_targets(const ModeReport& hybrid, const ModeReport& every_frame,
                                       const BenchTargets& targets = {});
// Side-by-side table (hybrid, every-frame, ratio every-frame / hybrid) and the target checks.
std::string comparison_text(const ModeReport& hybrid, const ModeReport& every_frame,
                            const std::vector<TargetCheck>& checks);
// hs-bench-tracker --mono: the same hybrid tracker on the stereo rig and on cam0 alone.
std::string rig_comparison_text(const ModeReport& stereo, const ModeReport& mono);
nlohmann::json comparison_json(const ModeReport& hybrid, const ModeReport& every_frame,
                               const std::vector<TargetCheck>& checks);

// Writes trajectory.tum, timing.csv and, with ground truth, eval.json + eval.png into
// `out_dir`; returns the printed summary.
std::string write_run_outputs(const std::string& out_dir, const OfflineRunResult& result);

}  // namespace hs
