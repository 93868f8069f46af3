#include "tracker/offline/run_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <sstream>

#include "common/core/atomic_file.h"
#include "common/eval/plot.h"

namespace hs {

TimeStats time_stats(std::vector<double> ms) {
  TimeStats s;
  s.count = ms.size();
  if (ms.empty()) return s;
  std::sort(ms.begin(), ms.end());
  const auto pct = [&](double p) {
    return ms[std::min(ms.size() - 1, static_cast<size_t>(std::ceil(p * ms.size())) - 1)];
  };
  s.total_ms = std::accumulate(ms.begin(), ms.end(), 0.0);
  s.mean = s.total_ms / static_cast<double>(ms.size());
  s.median = ms.size() % 2 ? ms[ms.size() / 2] : 0.5 * (ms[ms.size() / 2 - 1] + ms[ms.size() / 2]);
  s.p95 = pct(0.95);
  s.p99 = pct(0.99);
  s.max = ms.back();
  return s;
}

TimingSummary summarise_timing(const OfflineRunResult& result) {
  std::vector<double> all, kf, non_kf;
  for (const FrameRecord& f : result.frames) {
    if (!f.accepted) continue;
    all.push_back(f.total_ms);
    (f.is_keyframe ? kf : non_kf).push_back(f.total_ms);
  }
  return {time_stats(all), time_stats(kf), time_stats(non_kf)};
}

std::string timing_text(const TimingSummary& t) {
  std::ostringstream o;
  char line[200];
  o << "tracking time per frame [ms]    count    total_s     mean   median      p95      p99      "
       "max\n";
  const auto row = [&](const char* name, const TimeStats& s) {
    std::snprintf(line, sizeof line, "  %-28s %7zu %10.3f %8.3f %8.3f %8.3f %8.3f %8.3f\n", name,
                  s.count, s.total_ms / 1000.0, s.mean, s.median, s.p95, s.p99, s.max);
    o << line;
  };
  row("all frames", t.all);
  row("keyframes", t.keyframe);
  row("non-keyframes", t.non_keyframe);
  return o.str();
}

std::optional<EvalResult> evaluate_run(const OfflineRunResult& result) {
  const Trajectory est = result.estimate();
  if (result.ground_truth.empty() || est.poses.size() < 3) return std::nullopt;
  EvalOptions o;
  o.align = AlignMode::kSe3;
  // RPE over 1 m as the paper's tables; per frame when the run covers less than a few metres.
  double path_m = 0.0;
  for (size_t i = 1; i < est.poses.size(); ++i)
    path_m += (est.poses[i].T_w_b.translation() - est.poses[i - 1].T_w_b.translation()).norm();
  if (path_m > 3.0) {
    o.rpe_delta = 1.0;
    o.rpe_delta_unit = DeltaUnit::kMeters;
  }
  return evaluate(result.ground_truth_trajectory(), est, o);
}

std::string write_run_outputs(const std::string& out_dir, const OfflineRunResult& result) {
  std::ostringstream o;
  save_tum(out_dir + "/trajectory.tum", result.estimate());
  write_timing_csv(out_dir + "/timing.csv", result);
  const TrackerCounters& c = result.counters;
  int tracked = 0, lost = 0;
  for (const FrameRecord& f : result.frames) {
    tracked += f.state == TrackState::kTracking || f.state == TrackState::kRelocalised;
    lost += f.state == TrackState::kLost;
  }
  o << "frames " << result.frames.size() << " (tracked " << tracked << ", lost " << lost
    << "), keyframes " << c.keyframes << ", relocalisations " << c.relocalisations << ", new maps "
    << c.reinitialisations << "\n";
  o << "rejected frames: out-of-order " << c.rejected_out_of_order << ", bad image "
    << c.rejected_bad_image << ", IMU clock " << c.rejected_clock_offset
    << "; missing right images " << c.missing_right_image << "; IMU gaps bridged " << c.imu_gaps
    << "\n";
  o << timing_text(summarise_timing(result));
  if (const auto eval = evaluate_run(result)) {
    o << summary_text(*eval);
    write_file_atomically(out_dir + "/eval.json", to_json(*eval).dump(2) + "\n");
    write_plot(out_dir + "/eval.png", *eval, "HS-SLAM tracker vs ground truth");
  }
  o << "outputs: " << out_dir << "/{trajectory.tum, timing.csv"
    << (result.ground_truth.empty() ? "" : ", eval.json, eval.png") << "}\n";
  return o.str();
}

}  // namespace hs
