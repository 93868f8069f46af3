// Loop detection and closing in the mapper on simulated drives, checked against the simulator's
// ground truth: the second lap of vehicle_loop is recognised with relative poses at the
// centimetre and closing the loop shrinks the final trajectory's error; the look-alike street
// (everything repeats every 20 m) closes nothing although its places verify.
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>

#include "mapper/mapper.h"
#include "mapper/offline/mapper_report.h"
#include "tracker/offline/run_report.h"

namespace hs {
namespace {

struct LoopRun {
  MapperRunStats stats;
  MapperCounters counters;
  TrackerCounters tracker;
  std::vector<NavState> ground_truth;
  std::vector<FrameRecord> frames;
  sim::Scenario scenario;
  double final_ate_m = 0.0;  // frames on the mapper's keyframe poses at the end
};

// `close_loops` false: loops are detected (and reported) but neither closed nor fused.
// `background_full_ba`: a full BA after a closure, landing whenever it ends, as in hs-mapper
// with it enabled (not reproducible). `tweak` changes any other mapper option.
LoopRun run(sim::Scenario s, bool close_loops = true, bool background_full_ba = false,
            const std::function<void(MapperOptions&)>& tweak = {}) {
  TrackerOptions options;
  options.calib = s.camera.calib;
  MapperOptions mapper_options;
  mapper_options.loop_closing.enabled = close_loops;
  mapper_options.fuse_revisits = close_loops;
  mapper_options = reproducible(mapper_options);
  mapper_options.full_ba.enabled = background_full_ba;
  mapper_options.full_ba.background = background_full_ba;
  if (tweak) tweak(mapper_options);
  Mapper mapper(options.calib, mapper_options);
  LoopRun out;
  OfflineRunOptions run_options;
  run_options.back_end = in_process_back_end(mapper, out.stats);
  run_options.atlas = in_process_atlas(mapper);
  sim::DatasetGenerator gen(s);
  const OfflineRunResult result = run_offline(options, sim_source(gen), run_options);
  finish_back_end(mapper, out.stats);
  out.ground_truth = result.ground_truth;
  out.frames = result.frames;
  out.scenario = s;
  out.counters = mapper.counters();
  out.tracker = result.counters;
  out.final_ate_m = evaluate_run(result, result.keyframe_relative_estimate([&](int64_t id) {
                      return mapper.keyframe_pose(id);
                    }))->ape.stats.rmse;
  return out;
}

LoopRun run(const std::string& name, double duration_s, bool close_loops = true,
            bool background_full_ba = false) {
  sim::Scenario s = sim::load_scenario(HS_SOURCE_DIR "/config/sim/" + name + ".yaml");
  s.duration_s = duration_s;
  return run(s, close_loops, background_full_ba);
}

const NavState& truth_at(const std::vector<NavState>& gt, int64_t t_ns) {
  const auto it = std::lower_bound(gt.begin(), gt.end(), t_ns,
                                   [](const NavState& s, int64_t t) { return s.t_ns < t; });
  if (it == gt.end() || it->t_ns != t_ns) throw std::runtime_error("no ground truth at a keyframe");
  return *it;
}

// The car drives its 190 m block twice; the second lap starts at 52 s. Detection alone (no
// closing, no fusion) recognises the second lap keyframe after keyframe; closing the first loop
// and fusing the laps' points makes the later revisits share points with the first lap (no
// more loops to find: bundle adjustment holds the laps together). Measured over the full 102 s:
// detection alone 315 loops from 634 keyframes, none off by more than 3.3 cm / 0.13 deg, final
// ATE 4.71 cm; with closing and fusion: 1 loop closed, final ATE 1.52 cm (0.32x on this seed;
// the 0.3x is over seeds 1-10: tools/seed_sweep.sh, README).
TEST(LoopDetection, TheSecondLapOfVehicleLoopIsRecognisedAtTheCentimetreAndClosed) {
  const LoopRun r = run("vehicle_loop", 102.0);
  const LoopRun open = run("vehicle_loop", 102.0, false);
  EXPECT_GE(open.counters.loops_detected, 100);
  EXPECT_GE(r.counters.loops_closed, 1);
  EXPECT_GT(r.counters.points_fused, 1000);
  // After the closure the second lap's fused tracks weigh as detections (ties_across_a_loop).
  EXPECT_GT(r.counters.points_fused_as_ties, 1000);
  EXPECT_LT(r.final_ate_m, 0.6 * open.final_ate_m) << "open loop " << open.final_ate_m << " m";
  std::vector<LoopFound> loops = open.stats.loops;
  loops.insert(loops.end(), r.stats.loops.begin(), r.stats.loops.end());
  double worst_m = 0, worst_deg = 0;
  for (const LoopFound& l : loops) {
    const Eigen::Isometry3d T_c_q = truth_at(r.ground_truth, l.candidate_t_ns).T_w_b().inverse() *
                                    truth_at(r.ground_truth, l.query_t_ns).T_w_b();
    const double err_m = (l.T_c_q.translation() - T_c_q.translation()).norm();
    const double err_deg =
        Eigen::AngleAxisd(l.T_c_q.linear().transpose() * T_c_q.linear()).angle() * 180 / M_PI;
    EXPECT_LT(err_m, 0.05) << "keyframe at " << l.query_t_ns << " vs " << l.candidate_t_ns;
    EXPECT_LT(err_deg, 0.5) << "keyframe at " << l.query_t_ns << " vs " << l.candidate_t_ns;
    EXPECT_GT(l.path_m, 150.0);  // a lap later, not a neighbour
    worst_m = std::max(worst_m, err_m);
    worst_deg = std::max(worst_deg, err_deg);
  }
  std::printf(
      "%ld loops in %ld keyframes, %ld closed; worst relative pose error %.1f mm, %.2f deg; "
      "final ATE %.2f cm, %.2f cm without loop closing\n",
      static_cast<long>(open.counters.loops_detected), static_cast<long>(r.counters.loop_queries),
      static_cast<long>(r.counters.loops_closed), worst_m * 1e3, worst_deg, r.final_ate_m * 100,
      open.final_ate_m * 100);
}

// room_mav flies round one room for 40 s: loops are found but its drift (0.3 cm) is below what
// a loop measures, so closing and fusing must not make it worse.
TEST(LoopDetection, ClosingLoopsDoesNotSpoilASmallDriftFreeMap) {
  const LoopRun r = run("room_mav", 40.0);
  const LoopRun open = run("room_mav", 40.0, false);
  EXPECT_GT(open.counters.loops_detected, 0);
  EXPECT_LE(r.final_ate_m, 1.1 * open.final_ate_m) << "open loop " << open.final_ate_m << " m";
  // No loop closed: fused tracks keep the tracked weight (a tie would cost this map accuracy).
  EXPECT_EQ(r.counters.loops_closed, 0);
  EXPECT_EQ(r.counters.points_fused_as_ties, 0);
  std::printf(
      "room_mav: %ld loops detected; with closing and fusion %ld closed, %ld points fused, final "
      "ATE %.2f cm, %.2f cm without\n",
      static_cast<long>(open.counters.loops_detected), static_cast<long>(r.counters.loops_closed),
      static_cast<long>(r.counters.points_fused), r.final_ate_m * 100, open.final_ate_m * 100);
}

// Measured: 395 look-alike places verified geometrically (20.0 m from where odometry puts the
// car), every one refused as an implausible drift.
TEST(LoopDetection, ALookAlikeStreetClosesNoLoop) {
  const LoopRun r = run("lookalike_street", 48.0);
  EXPECT_EQ(r.counters.loops_detected, 0);
  EXPECT_GT(r.counters.places_implausible, 50);  // the look-alikes were there and were verified
  std::printf("%ld look-alike places verified and refused in %ld keyframes\n",
              static_cast<long>(r.counters.places_implausible),
              static_cast<long>(r.counters.loop_queries));
}

// As hs-mapper runs it when enabled: the full BA after vehicle_loop's closure (at 51 s) in its own
// thread while the tracker goes on as fast as it can, its result landing at the first keyframe
// after it ended; the keyframes that arrived meanwhile move with it.
TEST(LoopDetection, AFullBaInTheBackgroundLandsWhileMappingGoesOn) {
  const LoopRun r = run("vehicle_loop", 58.0, true, true);
  EXPECT_GE(r.counters.loops_closed, 1);
  ASSERT_GE(r.counters.full_bas, 1);
  ASSERT_FALSE(r.stats.full_ba_moved.empty());
  EXPECT_GT(r.stats.full_ba_moved.front(), 0);
  EXPECT_LT(r.final_ate_m, 0.02);
  std::printf("background full BA: %.0f ms, %.0f keyframes arrived meanwhile; final ATE %.2f cm\n",
              r.stats.full_ba_ms.front(), r.stats.full_ba_moved.front(), r.final_ate_m * 100);
}

// room_mav with 2 s of black frames from 15 s, tracker and mapper: the IMU carries the pose
// over the blackout and the tracker starts a new local map there that continues the map (same
// map id, same mapper world). The room has a look-alike 90 deg round, which the tracker's
// relocaliser and the mapper's place check both verify: the tracker refuses it (IMU gate), and
// the mapper must not take it for a loop either. Measured: the first frame after the blackout
// TRACKING in map id 0, no loop, final ATE 0.75 cm (a false merge with the look-alike, when the
// new local map was a world of its own, made it 136 cm).
TEST(LoopDetection, AfterABlackoutTheMapContinuesAndTheRoomsLookAlikeClosesNothing) {
  const LoopRun r = run("blackout", 20.0);
  EXPECT_EQ(r.counters.maps_merged, 0);
  EXPECT_EQ(r.counters.loops_detected, 0);
  EXPECT_LT(r.final_ate_m, 0.02);
  ASSERT_EQ(r.scenario.events.blackouts.size(), 1u);
  const int64_t end_ns = r.scenario.start_time_ns + r.scenario.events.blackouts[0].end_ns;
  int after = 0;
  bool tracking = false;
  for (const FrameRecord& f : r.frames) {
    if (f.t_ns <= end_ns) continue;
    ++after;
    if (f.state == TrackState::kTracking || f.state == TrackState::kRelocalised) {
      tracking = true;
      EXPECT_EQ(f.map_id, 0) << "the map continues: " << f.message;
      break;
    }
  }
  EXPECT_TRUE(tracking);
  EXPECT_LE(after, 10) << "frames after the blackout before tracking again";
  std::printf(
      "blackout: tracking again %d frames after it, %ld places refused, final ATE %.2f cm\n", after,
      static_cast<long>(r.counters.places_implausible), r.final_ate_m * 100);
}

// A 4.5 s blackout, longer than the IMU may bridge (3 s), ending where the room was seen
// before: the lost tracker sends its first frame with images to the mapper's atlas, which
// places it, and the tracker continues in the room's map from the next frame, in the map id it
// offered (joined to the room's world), instead of in a new map merged later. The room's two
// look-alikes (a 90 deg one, one 1.8 m off) verify too and are refused by the IMU-carried guess.
// Measured: tracking again 2 frames after the blackout, 1.8 cm from where the truth puts it
// relative to the last frame before (12.7 cm dead-reckoned); final ATE 2.61 cm. The same with
// the local BA's first round stopped at 1e-4: its corrections once left the tracker a
// dead-reckoned pose its frame-to-frame matching accepted 13 cm off, on 15 inliers, without
// asking the atlas; after a loss the IMU cannot bridge the tracker no longer tracks from it.
TEST(LoopDetection, AfterALongBlackoutTheAtlasPlacesTheLostTracker) {
  for (const double screening : {1e-6, 1e-4}) {
    SCOPED_TRACE("local BA screening_function_tolerance " + std::to_string(screening));
    sim::Scenario s = sim::load_scenario(HS_SOURCE_DIR "/config/sim/blackout.yaml");
    s.duration_s = 34.0;
    ASSERT_EQ(s.events.blackouts.size(), 1u);
    s.events.blackouts[0] = {24'500'000'000, 29'000'000'000};
    const LoopRun r = run(s, true, false,
                          [&](MapperOptions& o) { o.ba.screening_function_tolerance = screening; });
    EXPECT_EQ(r.tracker.atlas_relocalisations, 1);
    EXPECT_EQ(r.counters.relocalisations, 1);
    EXPECT_EQ(r.counters.maps_merged, 0);
    EXPECT_LT(r.final_ate_m, 0.03);

    const int64_t start_ns = s.start_time_ns + s.events.blackouts[0].start_ns;
    const int64_t end_ns = s.start_time_ns + s.events.blackouts[0].end_ns;
    const FrameRecord* before = nullptr;
    const FrameRecord* after = nullptr;
    int frames_after = 0;
    for (const FrameRecord& f : r.frames) {
      if (f.t_ns < start_ns && f.state == TrackState::kTracking) before = &f;
      if (f.t_ns <= end_ns) continue;
      ++frames_after;
      if (f.state == TrackState::kTracking) {
        after = &f;
        break;
      }
    }
    ASSERT_TRUE(before && after);
    EXPECT_LE(frames_after, 3) << "frames after the blackout before tracking again";
    EXPECT_NE(after->map_id, 0) << "a stated jump: " << after->message;
    const Eigen::Isometry3d moved = before->nav.T_w_b().inverse() * after->nav.T_w_b();
    const Eigen::Isometry3d truth = truth_at(r.ground_truth, before->t_ns).T_w_b().inverse() *
                                    truth_at(r.ground_truth, after->t_ns).T_w_b();
    const double err_m = (moved.translation() - truth.translation()).norm();
    EXPECT_LT(err_m, 0.03) << after->message;
    std::printf(
        "long blackout (screening %.0e): tracking again %d frames after it, in map id %d, %.1f cm "
        "from the truth relative to before it; atlas requests %ld; final ATE %.2f cm\n",
        screening, frames_after, after->map_id, err_m * 100,
        static_cast<long>(r.tracker.atlas_requests), r.final_ate_m * 100);
  }
}

}  // namespace
}  // namespace hs
