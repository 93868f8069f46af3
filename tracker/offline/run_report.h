#pragma once
// Summaries of an offline run: timing statistics (the paper's Table 4 layout) and the
// trajectory evaluation against ground truth.
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
  TimeStats all, keyframe, non_keyframe;  // per-frame tracking time, ms (accepted frames)
};

TimingSummary summarise_timing(const OfflineRunResult& result);
std::string timing_text(const TimingSummary& t);

// ATE/RPE of the run's estimate against its ground truth (SE(3) alignment, RPE over 1 m as
// the paper's tables), if it has ground truth.
std::optional<EvalResult> evaluate_run(const OfflineRunResult& result);

// Writes trajectory.tum, timing.csv and, with ground truth, eval.json + eval.png into
// `out_dir`; returns the printed summary.
std::string write_run_outputs(const std::string& out_dir, const OfflineRunResult& result);

}  // namespace hs
