#include "tracker/offline/run_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <sstream>

#include "common/core/atomic_file.h"
#include "common/core/error.h"
#include "common/eval/plot.h"

namespace hs {

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TimeStats, count, total_ms, mean, median, p95, p99, max)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TimingSummary, all, keyframe, non_keyframe)

namespace {

void count_states(const OfflineRunResult& result, int& tracked, int& lost) {
  tracked = lost = 0;
  for (const FrameRecord& f : result.frames) {
    tracked += f.state == TrackState::kTracking || f.state == TrackState::kRelocalised;
    lost += f.state == TrackState::kLost;
  }
}

// every-frame / hybrid; NaN (JSON null) when hybrid has no figure.
double speedup(double every_frame, double hybrid) {
  return hybrid > 0.0 ? every_frame / hybrid : std::nan("");
}

std::string format(const char* fmt, double a, double b = 0.0) {
  char buf[96];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}

}  // namespace

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
    // Frames waiting for the IMU gravity window are not tracked: they would dilute the figures.
    if (!f.accepted || f.state == TrackState::kInitialising) continue;
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
  return evaluate_run(result, result.estimate());
}

std::optional<EvalResult> evaluate_run(const OfflineRunResult& result, const Trajectory& est) {
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

namespace {

// evaluate_run, with the reason in `error` when the evaluation is impossible (e.g. a
// straight-line path has no unique alignment) rather than an exception.
std::optional<EvalResult> try_evaluate(const OfflineRunResult& result, std::string& error) {
  try {
    return evaluate_run(result);
  } catch (const InputError& e) {
    error = e.what();
    return std::nullopt;
  }
}

}  // namespace

ModeReport mode_report(const std::string& mode, const OfflineRunResult& result) {
  ModeReport r;
  r.mode = mode;
  r.frames = result.frames.size();
  count_states(result, r.tracked, r.lost);
  r.timing = summarise_timing(result);
  if (const auto eval = try_evaluate(result, r.ate_error)) r.ate_rmse_m = eval->ape.stats.rmse;
  return r;
}

nlohmann::json to_json(const ModeReport& r) {
  return {{"mode", r.mode},
          {"frames", r.frames},
          {"tracked", r.tracked},
          {"lost", r.lost},
          {"timing_ms", r.timing},
          {"ate_rmse_m", r.ate_rmse_m ? nlohmann::json(*r.ate_rmse_m) : nlohmann::json()},
          {"ate_error", r.ate_error},
          {"peak_rss_mb", r.peak_rss_mb},
          {"cpu_s", r.cpu_s}};
}

ModeReport mode_report_from_json(const nlohmann::json& j) {
  try {
    ModeReport r;
    j.at("mode").get_to(r.mode);
    j.at("frames").get_to(r.frames);
    j.at("tracked").get_to(r.tracked);
    j.at("lost").get_to(r.lost);
    j.at("timing_ms").get_to(r.timing);
    if (!j.at("ate_rmse_m").is_null()) r.ate_rmse_m = j.at("ate_rmse_m").get<double>();
    j.at("ate_error").get_to(r.ate_error);
    j.at("peak_rss_mb").get_to(r.peak_rss_mb);
    j.at("cpu_s").get_to(r.cpu_s);
    return r;
  } catch (const nlohmann::json::exception& e) {
    throw InputError("mode report JSON", e.what());
  }
}

std::vector<TargetCheck> check_targets(const ModeReport& hy, const ModeReport& ef,
                                       const BenchTargets& t) {
  std::vector<TargetCheck> out;
  const auto add = [&](std::string name, std::string value, std::optional<bool> met) {
    out.push_back({std::move(name), std::move(value), met});
  };
  const auto ratio_check = [&](std::string name, double ratio, double target) {
    if (std::isnan(ratio))
      add(std::move(name), "no hybrid frames of that kind", std::nullopt);
    else
      add(std::move(name), format("%.2fx", ratio), ratio >= target);
  };
  const TimingSummary &h = hy.timing, &e = ef.timing;
  add(format("hybrid per-frame mean <= %g ms", t.hybrid_mean_ms), format("%.3f ms", h.all.mean),
      h.all.count ? std::optional<bool>(h.all.mean <= t.hybrid_mean_ms) : std::nullopt);
  ratio_check(format("non-keyframes >= %gx faster than every-frame", t.non_keyframe_speedup),
              speedup(e.non_keyframe.mean, h.non_keyframe.mean), t.non_keyframe_speedup);
  ratio_check(format("all frames >= %gx faster than every-frame", t.overall_speedup),
              speedup(e.all.mean, h.all.mean), t.overall_speedup);
  if (hy.ate_rmse_m && ef.ate_rmse_m)
    add("hybrid ATE no worse than every-frame",
        format("%.4f m vs %.4f m", *hy.ate_rmse_m, *ef.ate_rmse_m),
        *hy.ate_rmse_m <= *ef.ate_rmse_m);
  else
    add("hybrid ATE no worse than every-frame", "no ATE (see above)", std::nullopt);
  add(format("hybrid peak RSS <= %g MB", t.peak_rss_mb), format("%.1f MB", hy.peak_rss_mb),
      hy.peak_rss_mb <= t.peak_rss_mb);
  return out;
}

namespace {

// Two runs side by side, with the ratio b / a of their times.
std::string side_by_side(const ModeReport& hy, const ModeReport& ef) {
  std::ostringstream o;
  char line[160];
  std::snprintf(line, sizeof line, "%-32s %12s %12s %12s\n", "", hy.mode.c_str(), ef.mode.c_str(),
                "ratio");
  o << line;
  // A row of two figures ("-" for none); the ratio column only for times.
  const auto cell = [](const char* fmt, double v) { return std::isnan(v) ? "-" : format(fmt, v); };
  const auto row = [&](const char* name, double h, double e, const char* fmt, bool ratio) {
    std::snprintf(line, sizeof line, "%-32s %12s %12s %12s\n", name, cell(fmt, h).c_str(),
                  cell(fmt, e).c_str(), ratio ? cell("%.2f", speedup(e, h)).c_str() : "");
    o << line;
  };
  const auto count = [](size_t n) { return static_cast<double>(n); };
  const auto stats_rows = [&](const char* what, const TimeStats& h, const TimeStats& e) {
    const std::string w = what;
    row((w + " mean [ms]").c_str(), h.mean, e.mean, "%.3f", true);
    row((w + " median [ms]").c_str(), h.median, e.median, "%.3f", true);
    row((w + " p95 [ms]").c_str(), h.p95, e.p95, "%.3f", true);
    row((w + " p99 [ms]").c_str(), h.p99, e.p99, "%.3f", true);
    row((w + " max [ms]").c_str(), h.max, e.max, "%.3f", true);
  };
  const TimingSummary &h = hy.timing, &e = ef.timing;
  row("frames", count(hy.frames), count(ef.frames), "%.0f", false);
  row("tracked frames", hy.tracked, ef.tracked, "%.0f", false);
  row("lost frames", hy.lost, ef.lost, "%.0f", false);
  row("total tracking time [s]", h.all.total_ms / 1e3, e.all.total_ms / 1e3, "%.3f", true);
  stats_rows("per frame", h.all, e.all);
  row("keyframes", count(h.keyframe.count), count(e.keyframe.count), "%.0f", false);
  stats_rows("keyframe", h.keyframe, e.keyframe);
  row("non-keyframes", count(h.non_keyframe.count), count(e.non_keyframe.count), "%.0f", false);
  stats_rows("non-keyframe", h.non_keyframe, e.non_keyframe);
  row("ATE RMSE, SE(3) aligned [m]", hy.ate_rmse_m.value_or(std::nan("")),
      ef.ate_rmse_m.value_or(std::nan("")), "%.4f", false);
  for (const ModeReport* r : {&hy, &ef})
    if (!r->ate_error.empty()) o << "  no ATE for " << r->mode << ": " << r->ate_error << "\n";
  row("peak RSS [MB]", hy.peak_rss_mb, ef.peak_rss_mb, "%.1f", false);
  row("process CPU, incl. image I/O [s]", hy.cpu_s, ef.cpu_s, "%.2f", true);
  return o.str();
}

}  // namespace

std::string rig_comparison_text(const ModeReport& stereo, const ModeReport& mono) {
  return "stereo vs mono rig (hybrid; mono times from its two-view start on):\n" +
         side_by_side(stereo, mono);
}

std::string comparison_text(const ModeReport& hy, const ModeReport& ef,
                            const std::vector<TargetCheck>& checks) {
  std::ostringstream o;
  char line[160];
  o << side_by_side(hy, ef);
  const TimingSummary &h = hy.timing, &e = ef.timing;
  // The paper's "Improvements" column: reduction of the mean time per frame.
  if (e.all.mean > 0.0)
    o << format("improvement of the per-frame mean (1 - hybrid/every-frame): %.1f%%\n",
                100.0 * (1.0 - h.all.mean / e.all.mean));
  o << "targets:\n";
  for (const TargetCheck& c : checks) {
    std::snprintf(line, sizeof line, "  %-9s %-48s %s\n",
                  !c.met   ? "[n/a]"
                  : *c.met ? "[met]"
                           : "[NOT MET]",
                  c.name.c_str(), c.value.c_str());
    o << line;
  }
  return o.str();
}

nlohmann::json comparison_json(const ModeReport& hy, const ModeReport& ef,
                               const std::vector<TargetCheck>& checks) {
  const TimingSummary &h = hy.timing, &e = ef.timing;
  nlohmann::json targets = nlohmann::json::array();
  for (const TargetCheck& c : checks)
    targets.push_back(
        {{"name", c.name}, {"value", c.value}, {"met", c.met ? nlohmann::json(*c.met) : nullptr}});
  return {{"hybrid", to_json(hy)},
          {"every_frame", to_json(ef)},
          {"every_frame_over_hybrid",
           {{"total", speedup(e.all.total_ms, h.all.total_ms)},
            {"mean", speedup(e.all.mean, h.all.mean)},
            {"keyframe_mean", speedup(e.keyframe.mean, h.keyframe.mean)},
            {"non_keyframe_mean", speedup(e.non_keyframe.mean, h.non_keyframe.mean)}}},
          {"targets", targets}};
}

std::string write_run_outputs(const std::string& out_dir, const OfflineRunResult& result) {
  std::ostringstream o;
  save_tum(out_dir + "/trajectory.tum", result.estimate());
  write_timing_csv(out_dir + "/timing.csv", result);
  const TrackerCounters& c = result.counters;
  int tracked = 0, lost = 0;
  count_states(result, tracked, lost);
  o << "frames " << result.frames.size() << " (tracked " << tracked << ", lost " << lost
    << "), keyframes " << c.keyframes << ", relocalisations " << c.relocalisations
    << " (rejected by the IMU gate " << c.relocalisations_rejected << "), local maps restarted "
    << c.reinitialisations << " (" << c.maps_continued << " continuing the map, "
    << c.atlas_relocalisations << " placed by the atlas of " << c.atlas_requests << " asked)"
    << (c.scale_corrections > 0 ? ", mono scale corrections " + std::to_string(c.scale_corrections)
                                : std::string())
    << "\n";
  o << "rejected frames: out-of-order " << c.rejected_out_of_order << ", bad image "
    << c.rejected_bad_image << ", IMU clock " << c.rejected_clock_offset
    << "; missing right images " << c.missing_right_image << "; IMU gaps bridged " << c.imu_gaps
    << " (frames on vision alone " << c.frames_without_imu << ")\n";
  o << timing_text(summarise_timing(result));
  std::string eval_error;
  const std::optional<EvalResult> eval = try_evaluate(result, eval_error);
  if (!eval_error.empty()) o << "no evaluation: " << eval_error << "\n";
  if (eval) {
    o << summary_text(*eval);
    // The scale a Sim(3) alignment finds: a mono run's scale error (metric stereo: near 1).
    EvalOptions sim3 = eval->options;
    sim3.align = AlignMode::kSim3;
    try {
      const EvalResult s = evaluate(result.ground_truth_trajectory(), result.estimate(), sim3);
      o << "Sim(3) alignment: scale " << s.alignment.s << " (error "
        << 100.0 * std::abs(s.alignment.s - 1.0) << " %), ATE " << s.ape.stats.rmse << " m\n";
    } catch (const InputError& e) {
      o << "no Sim(3) alignment: " << e.what() << "\n";
    }
    // The ground truth beside the estimate, so hs-eval's other options (Sim(3), RPE deltas) and
    // evo can be run on the pair.
    save_tum(out_dir + "/groundtruth.tum", result.ground_truth_trajectory());
    write_file_atomically(out_dir + "/eval.json", to_json(*eval).dump(2) + "\n");
    write_plot(out_dir + "/eval.png", *eval, "HS-SLAM tracker vs ground truth");
  }
  o << "outputs: " << out_dir << "/{trajectory.tum, timing.csv"
    << (eval ? ", groundtruth.tum, eval.json, eval.png" : "") << "}\n";
  return o.str();
}

}  // namespace hs
