// Timing statistics and the benchmark's hybrid vs every-frame comparison (run_report.h).
#include "tracker/offline/run_report.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "common/core/error.h"

namespace hs {
namespace {

TEST(TimeStats, NearestRankPercentilesOfOneToHundred) {
  std::vector<double> ms(100);
  std::iota(ms.begin(), ms.end(), 1.0);
  std::reverse(ms.begin(), ms.end());  // input order must not matter
  const TimeStats s = time_stats(ms);
  EXPECT_EQ(s.count, 100u);
  EXPECT_DOUBLE_EQ(s.total_ms, 5050.0);
  EXPECT_DOUBLE_EQ(s.mean, 50.5);
  EXPECT_DOUBLE_EQ(s.median, 50.5);
  EXPECT_DOUBLE_EQ(s.p95, 95.0);
  EXPECT_DOUBLE_EQ(s.p99, 99.0);
  EXPECT_DOUBLE_EQ(s.max, 100.0);
}

TEST(TimeStats, OddCountAndEmpty) {
  const TimeStats s = time_stats({3.0, 1.0, 2.0});
  EXPECT_DOUBLE_EQ(s.median, 2.0);
  EXPECT_DOUBLE_EQ(s.p95, 3.0);
  EXPECT_EQ(time_stats({}).count, 0u);
}

FrameRecord frame(bool accepted, bool keyframe, float ms, TrackState state) {
  FrameRecord f;
  f.accepted = accepted;
  f.is_keyframe = keyframe;
  f.total_ms = ms;
  f.state = state;
  return f;
}

TEST(TimingSummary, SplitsKeyframesAndSkipsRejectedAndInitialisingFrames) {
  OfflineRunResult run;
  run.frames = {frame(true, true, 10.0f, TrackState::kTracking),
                frame(true, false, 2.0f, TrackState::kTracking),
                frame(false, false, 50.0f, TrackState::kLost),
                frame(true, false, 4.0f, TrackState::kLost),
                frame(true, false, 0.1f, TrackState::kInitialising)};
  const TimingSummary t = summarise_timing(run);
  EXPECT_EQ(t.all.count, 3u);
  EXPECT_DOUBLE_EQ(t.all.total_ms, 16.0);
  EXPECT_EQ(t.keyframe.count, 1u);
  EXPECT_DOUBLE_EQ(t.keyframe.mean, 10.0);
  EXPECT_EQ(t.non_keyframe.count, 2u);
  EXPECT_DOUBLE_EQ(t.non_keyframe.mean, 3.0);

  const ModeReport r = mode_report("hybrid", run);
  EXPECT_EQ(r.frames, 5u);
  EXPECT_EQ(r.tracked, 2);
  EXPECT_EQ(r.lost, 2);
  EXPECT_FALSE(r.ate_rmse_m.has_value());  // no ground truth
}

// A straight-line path has no unique SE(3) alignment: the report says so instead of throwing.
TEST(ModeReport, StraightLineHasNoAteButAReason) {
  OfflineRunResult run;
  for (int i = 0; i < 10; ++i) {
    FrameRecord f = frame(true, i == 0, 1.0f, TrackState::kTracking);
    f.t_ns = i * 50'000'000;
    f.nav.t_ns = f.t_ns;
    f.nav.p_w_b = Eigen::Vector3d(0.1 * i, 0.0, 0.0);
    run.frames.push_back(f);
    run.ground_truth.push_back(f.nav);
  }
  const ModeReport r = mode_report("hybrid", run);
  EXPECT_FALSE(r.ate_rmse_m.has_value());
  EXPECT_FALSE(r.ate_error.empty());
}

// A report whose per-frame times are all `ms`, with `keyframes` of them at `kf_ms`.
ModeReport report(const std::string& mode, double ms, double kf_ms, size_t frames,
                  size_t keyframes) {
  ModeReport r;
  r.mode = mode;
  r.frames = frames;
  r.tracked = static_cast<int>(frames);
  std::vector<double> all(frames - keyframes, ms), kf(keyframes, kf_ms);
  r.timing.non_keyframe = time_stats(all);
  r.timing.keyframe = time_stats(kf);
  all.insert(all.end(), kf.begin(), kf.end());
  r.timing.all = time_stats(all);
  r.ate_rmse_m = 0.02;
  r.peak_rss_mb = 80.0;
  r.cpu_s = 1.5;
  return r;
}

TEST(ModeReport, JsonRoundTrip) {
  ModeReport r = report("every-frame", 9.0, 20.0, 100, 10);
  for (const std::optional<double> ate : {std::optional<double>(0.0123), std::optional<double>()}) {
    r.ate_rmse_m = ate;
    r.ate_error = ate ? "" : "degenerate alignment";
    const ModeReport back = mode_report_from_json(nlohmann::json::parse(to_json(r).dump()));
    EXPECT_EQ(back.mode, r.mode);
    EXPECT_EQ(back.frames, r.frames);
    EXPECT_EQ(back.tracked, r.tracked);
    EXPECT_EQ(back.timing.keyframe.count, r.timing.keyframe.count);
    EXPECT_DOUBLE_EQ(back.timing.all.mean, r.timing.all.mean);
    EXPECT_DOUBLE_EQ(back.timing.non_keyframe.p99, r.timing.non_keyframe.p99);
    EXPECT_EQ(back.ate_rmse_m, r.ate_rmse_m);
    EXPECT_EQ(back.ate_error, r.ate_error);
    EXPECT_DOUBLE_EQ(back.peak_rss_mb, r.peak_rss_mb);
  }
  nlohmann::json broken = to_json(r);
  broken.erase("timing_ms");
  EXPECT_THROW(mode_report_from_json(broken), InputError);
}

std::optional<bool> met(const std::vector<TargetCheck>& checks, const std::string& prefix) {
  for (const TargetCheck& c : checks)
    if (c.name.rfind(prefix, 0) == 0) return c.met;
  ADD_FAILURE() << "no target starting with " << prefix;
  return std::nullopt;
}

TEST(CheckTargets, AllMetWhenHybridIsFastSmallAndAccurate) {
  const ModeReport hy = report("hybrid", 2.0, 12.0, 100, 10);  // mean 3.0
  const ModeReport ef = report("every-frame", 7.0, 16.0, 100, 10);
  const auto checks = check_targets(hy, ef);
  ASSERT_EQ(checks.size(), 5u);
  for (const TargetCheck& c : checks) EXPECT_EQ(c.met, std::optional<bool>(true)) << c.name;
  const std::string text = comparison_text(hy, ef, checks);
  EXPECT_NE(text.find("3.50"), std::string::npos) << text;  // non-keyframe ratio 7 / 2
  EXPECT_EQ(text.find("NOT MET"), std::string::npos) << text;
  const nlohmann::json j = comparison_json(hy, ef, checks);
  EXPECT_DOUBLE_EQ(j["every_frame_over_hybrid"]["non_keyframe_mean"].get<double>(), 3.5);
  EXPECT_DOUBLE_EQ(j["every_frame_over_hybrid"]["mean"].get<double>(),
                   ef.timing.all.mean / hy.timing.all.mean);
}

TEST(CheckTargets, EachFailureIsReported) {
  ModeReport hy = report("hybrid", 5.0, 12.0, 100, 10);  // mean 5.7 ms
  ModeReport ef = report("every-frame", 9.0, 16.0, 100, 10);
  hy.ate_rmse_m = 0.03;
  hy.peak_rss_mb = 151.0;
  const auto checks = check_targets(hy, ef);
  EXPECT_EQ(met(checks, "hybrid per-frame mean"), std::optional<bool>(false));
  EXPECT_EQ(met(checks, "non-keyframes"), std::optional<bool>(false));  // 1.8x
  EXPECT_EQ(met(checks, "all frames"), std::optional<bool>(false));     // 1.7x
  EXPECT_EQ(met(checks, "hybrid ATE"), std::optional<bool>(false));
  EXPECT_EQ(met(checks, "hybrid peak RSS"), std::optional<bool>(false));
  EXPECT_NE(comparison_text(hy, ef, checks).find("[NOT MET]"), std::string::npos);
}

TEST(CheckTargets, UnmeasurableTargetsAreNotApplicable) {
  ModeReport hy = report("hybrid", 2.0, 12.0, 10, 10);  // keyframes only
  const ModeReport ef = report("every-frame", 7.0, 16.0, 10, 1);
  hy.ate_rmse_m.reset();
  const auto checks = check_targets(hy, ef);
  EXPECT_FALSE(met(checks, "non-keyframes").has_value());
  EXPECT_FALSE(met(checks, "hybrid ATE").has_value());
  EXPECT_TRUE(comparison_json(hy, ef, checks)["targets"][1]["met"].is_null());
  const std::string text = comparison_text(hy, ef, checks);
  EXPECT_EQ(text.find("nan"), std::string::npos) << text;  // missing figures print as "-"
}

}  // namespace
}  // namespace hs
