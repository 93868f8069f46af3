// Mono-inertial operation (issue 10): the two-view start, vision alone until the IMU gives scale
// and gravity, then tracking with new points from keyframe pairs, alone or with the mapper.
// Scored with hs-eval's SE(3) alignment (the scale must be right), the Sim(3) scale beside it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "mapper/mapper.h"
#include "mapper/offline/mapper_report.h"
#include "tracker/offline/run_report.h"

namespace hs {
namespace {

const std::string kShared = HS_SOURCE_DIR "/../shared/data/euroc";

TrackerOptions mono_options(const StereoCalib& calib) {
  TrackerOptions options;
  options.calib = calib;
  options.stereo = false;
  return options;
}

struct MonoFigures {
  size_t first_tracked = 0;  // index of the first frame with a state
  double ate_m = 0.0;        // SE(3)
  double scale = 0.0;        // Sim(3): estimate to ground truth
  std::string last_wait;     // the last initialising message
};

MonoFigures figures(const OfflineRunResult& run, const Trajectory& est, const char* name) {
  MonoFigures f;
  f.first_tracked = run.frames.size();
  for (size_t i = 0; i < run.frames.size(); ++i) {
    if (run.frames[i].accepted && run.frames[i].state != TrackState::kInitialising) {
      f.first_tracked = i;
      break;
    }
    f.last_wait = run.frames[i].message;
  }
  const auto se3 = evaluate_run(run, est);
  if (!se3) return f;
  f.ate_m = se3->ape.stats.rmse;
  EvalOptions o = se3->options;
  o.align = AlignMode::kSim3;
  f.scale = evaluate(run.ground_truth_trajectory(), est, o).alignment.s;
  std::printf("%s: tracking from frame %zu of %zu, ATE %.2f cm (SE(3)), Sim(3) scale %.4f\n", name,
              f.first_tracked, run.frames.size(), 100 * f.ate_m, f.scale);
  return f;
}

// `drift_sigma`: the alignments' allowance for drifting vision attitudes (rad/s; the default's
// unless set).
OfflineRunResult room_mav(bool with_mapper, Trajectory* final_estimate,
                          std::optional<double> drift_sigma = std::nullopt) {
  sim::Scenario scenario = sim::load_scenario(HS_SOURCE_DIR "/config/sim/room_mav.yaml");
  scenario.duration_s = 40.0;
  TrackerOptions options = mono_options(scenario.camera.calib);
  if (drift_sigma) options.mono.alignment.vision_rotation_drift_sigma = *drift_sigma;
  Mapper mapper(options.calib, reproducible(MapperOptions{}));
  MapperRunStats stats;
  OfflineRunOptions run_options;
  if (with_mapper) run_options.back_end = in_process_back_end(mapper, stats);
  sim::DatasetGenerator gen(scenario);
  OfflineRunResult run = run_offline(options, sim_source(gen, false), run_options);
  *final_estimate =
      with_mapper
          ? run.keyframe_relative_estimate([&](int64_t id) { return mapper.keyframe_pose(id); })
          : run.estimate();
  return run;
}

// The tracker alone on cam0 of a real EuRoC piece; nullopt (the test skips) where it is absent.
std::optional<OfflineRunResult> real_cam0_run(const std::string& name) {
  const std::string dir = kShared + "/" + name;
  if (!std::filesystem::exists(dir)) return std::nullopt;
  EurocOptions eo;
  eo.use_cam1 = false;
  const EurocReader reader(dir, eo);
  EurocStream stream(reader);
  return run_offline(mono_options(read_stereo_calib(reader.mav0())), euroc_source(stream));
}

void expect_started_in_flight_and_never_lost(const OfflineRunResult& run, const MonoFigures& f) {
  ASSERT_LT(f.first_tracked, run.frames.size()) << "never initialised: " << f.last_wait;
  // room_mav holds still for 2 s: nothing to reconstruct from two views.
  EXPECT_GT(run.frames[f.first_tracked].t_ns - run.frames.front().t_ns, 2'000'000'000);
  for (size_t i = f.first_tracked; i < run.frames.size(); ++i)
    EXPECT_NE(run.frames[i].state, TrackState::kLost) << run.frames[i].message;
}

// room_mav from cam0 alone with the mapper: the targets (5 cm, 2% scale), online (the
// poses as the tracker published them) and on the mapper's final keyframes.
TEST(MonoAccuracy, RoomMavFromCam0WithTheMapperWithinFiveCentimetresAndTwoPercentScale) {
  Trajectory final_estimate;
  const OfflineRunResult run = room_mav(true, &final_estimate);
  const MonoFigures online = figures(run, run.estimate(), "room_mav mono + mapper, online");
  expect_started_in_flight_and_never_lost(run, online);
  EXPECT_LE(online.ate_m, 0.05);
  EXPECT_LE(std::abs(online.scale - 1.0), 0.02);
  const MonoFigures final = figures(run, final_estimate, "room_mav mono + mapper, final");
  EXPECT_LE(final.ate_m, 0.05);
  EXPECT_LE(std::abs(final.scale - 1.0), 0.02);
}

// The tracker alone has no bundle adjustment: its map drifts like a visual odometry, and only
// the IMU's checks of the map's scale hold that. Since the alignments allow for the attitude
// drift of the vision (vision_rotation_drift_sigma), the start's scale is right within about 3%
// and the checks are never sure enough to correct it (seeds 1-3: ATE 9.4 / 3.9 / 2.6 cm, Sim(3)
// scale error 3.1 / 1.1 / 0.3%; before: 14.1 / 3.8 / 7.3 cm). A bound against regressions, not the
// issue's target (the mapper's).
TEST(MonoAccuracy, RoomMavFromCam0TheTrackerAloneHoldsTheScale) {
  Trajectory estimate;
  const OfflineRunResult run = room_mav(false, &estimate);
  const MonoFigures f = figures(run, estimate, "room_mav mono, tracker alone");
  expect_started_in_flight_and_never_lost(run, f);
  EXPECT_LE(f.ate_m, 0.12);
  EXPECT_LE(std::abs(f.scale - 1.0), 0.04);
}

// Without that allowance (as before it) the start is worse and the checks, surer, do rescale the
// map, which holds the scale within 5% (seed 1: ATE 14.1 cm, Sim(3) scale 0.957).
TEST(MonoAccuracy, RoomMavFromCam0TheScaleChecksRescaleTheMap) {
  Trajectory estimate;
  const OfflineRunResult run = room_mav(false, &estimate, 0.0);
  const MonoFigures f = figures(run, estimate, "room_mav mono, tracker alone, no drift allowance");
  expect_started_in_flight_and_never_lost(run, f);
  EXPECT_GT(run.counters.scale_corrections, 0);
  EXPECT_LE(std::abs(f.scale - 1.0), 0.05);
}

// The real flying frames of V1_01 (left camera, real IMU), the tracker alone: the targets,
// started within the first 60 frames (frame 52), within 5 cm (0.7 cm) and its scale within 5%
// (Sim(3) 0.963). The mono odometry's attitudes drift 0.75 deg/s in pitch over the start's 2.6 s
// against the gyro and ground truth; taken for gyro bias they tilted gravity and made the scale
// 14.6% off until the alignment allowed for it.
TEST(MonoAccuracy, RealV1_01FlightStartsWithinSixtyFramesWithinFiveCentimetresAndFivePercentScale) {
  const std::optional<OfflineRunResult> real = real_cam0_run("V1_01_flight_cam0");
  if (!real) GTEST_SKIP() << "V1_01_flight_cam0 absent (real EuRoC data is only in CI)";
  const OfflineRunResult& run = *real;
  const MonoFigures f = figures(run, run.estimate(), "V1_01 flight mono, tracker alone");
  ASSERT_LT(f.first_tracked, 60u) << "not initialised within 60 frames: " << f.last_wait;
  EXPECT_LE(f.ate_m, 0.05);
  EXPECT_LE(std::abs(f.scale - 1.0), 0.05);
}

// The real static frames of V1_01, cam0 only: nothing moves, so no start however long.
TEST(MonoAccuracy, RealStaticFramesNeverInitialise) {
  const std::optional<OfflineRunResult> real = real_cam0_run("V1_01_static_stereo");
  if (!real) GTEST_SKIP() << "V1_01_static_stereo absent (real EuRoC data is only in CI)";
  const OfflineRunResult& run = *real;
  ASSERT_GT(run.frames.size(), 60u);
  for (const FrameRecord& f : run.frames)
    ASSERT_EQ(f.state, TrackState::kInitialising) << f.message;
  EXPECT_NE(run.frames.back().message.find("not enough motion"), std::string::npos)
      << run.frames.back().message;
}

}  // namespace
}  // namespace hs
