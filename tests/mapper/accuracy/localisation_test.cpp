// Saving a map and localising in it later (issue 7): vehicle_loop's first lap is mapped and
// saved; a new tracker and a mapper that loaded the file drive the second lap in
// localisation-only mode. The second lap must merge into the saved map within its first second
// of tracking, be at least as accurate as the first lap, and sit in the map where the truth
// puts it (the first lap's own alignment to the ground truth places it within the map's error);
// the map must come out unchanged.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "mapper/mapper.h"
#include "mapper/offline/mapper_report.h"
#include "tracker/offline/run_report.h"

namespace hs {
namespace {

constexpr double kFirstLapEndS = 53.0;  // vehicle_loop: 2 s hold, 3 s ramp, 190 m at 4 m/s

struct Lap {
  OfflineRunResult result;
  Trajectory final_estimate;  // frames on the mapper's keyframe poses at the end
  MapperCounters counters;
  MapFile map;
};

Lap drive(double skip_s, double duration_s, const MapFile* map) {
  sim::Scenario s = sim::load_scenario(HS_SOURCE_DIR "/config/sim/vehicle_loop.yaml");
  s.duration_s = duration_s;
  TrackerOptions options;
  options.calib = s.camera.calib;
  MapperOptions mapper_options;
  mapper_options.localisation_only = map != nullptr;
  Mapper mapper(options.calib, reproducible(mapper_options));
  if (map) mapper.load(*map);
  MapperRunStats stats;
  OfflineRunOptions run_options;
  run_options.back_end = in_process_back_end(mapper, stats);
  run_options.skip_ns = s_to_ns(skip_s);
  sim::DatasetGenerator gen(s);
  Lap lap;
  lap.result = run_offline(options, sim_source(gen), run_options);
  finish_back_end(mapper, stats);
  lap.final_estimate =
      lap.result.keyframe_relative_estimate([&](int64_t id) { return mapper.keyframe_pose(id); });
  lap.counters = mapper.counters();
  lap.map = mapper.map_file();
  return lap;
}

TEST(Localisation, TheSecondLapLocalisesInTheFirstLapsSavedMapWithoutChangingIt) {
  const Lap first = drive(0.0, kFirstLapEndS, nullptr);
  const std::string path =
      (std::filesystem::temp_directory_path() / "hs_localisation_test.hsmap").string();
  write_map_file(path, first.map);
  const MapFile loaded = read_map_file(path);
  std::filesystem::remove(path);
  const Lap second = drive(kFirstLapEndS, 102.0, &loaded);

  // Merged: the tracker stated the jump into the map's frame with a new map id.
  const FrameRecord* first_pose = nullptr;
  const FrameRecord* merged = nullptr;
  for (const FrameRecord& f : second.result.frames) {
    if (!f.accepted || f.state == TrackState::kInitialising) continue;
    if (!first_pose) first_pose = &f;
    if (f.map_id != first_pose->map_id) {
      merged = &f;
      break;
    }
  }
  ASSERT_NE(first_pose, nullptr);
  ASSERT_NE(merged, nullptr) << "the second lap never merged into the loaded map";
  EXPECT_EQ(second.counters.maps_merged, 1);
  const double merge_after_s = ns_to_s(merged->t_ns - first_pose->t_ns);
  EXPECT_LE(merge_after_s, 1.0);

  // The first lap's map aligned to the truth; the second lap in that same alignment.
  const EvalResult map_eval = *evaluate_run(first.result, first.final_estimate);
  Trajectory after_merge;
  for (const StampedPose& p : second.final_estimate.poses)
    if (p.t_ns >= merged->t_ns) after_merge.poses.push_back(p);
  Trajectory in_map = after_merge;
  apply_alignment(map_eval.alignment, in_map);
  EvalOptions none;
  const EvalResult lap2 = evaluate(second.result.ground_truth_trajectory(), in_map, none);
  const double lap1_m = map_eval.ape.stats.rmse;
  // The target, each lap aligned on its own as evo does it.
  const double lap2_own_m = evaluate_run(second.result, after_merge)->ape.stats.rmse;
  EXPECT_LE(lap2_own_m, lap1_m);
  // Localised in the map, not only accurate: in the map's alignment the second lap is off by no
  // more than the map itself (a lap tracked on its own is metres off there).
  EXPECT_LE(lap2.ape.stats.rmse, 1.1 * lap1_m);
  EXPECT_GT(lap2.matched.est.poses.size(), 800u);
  EXPECT_GT(second.counters.points_fused, 1000);

  // Localisation only: the map saved after the second lap is the loaded one.
  ASSERT_EQ(second.map.keyframes.size(), loaded.keyframes.size());
  for (size_t i = 0; i < loaded.keyframes.size(); ++i) {
    const MapperKeyframe& a = loaded.keyframes[i];
    const MapperKeyframe& b = second.map.keyframes[i];
    EXPECT_TRUE(b.state.T_w_b().isApprox(a.state.T_w_b(), 1e-12)) << "keyframe " << i;
    ASSERT_EQ(b.point_positions.size(), a.point_positions.size()) << "keyframe " << i;
  }
  std::printf(
      "first lap: %zu keyframes, ATE %.2f cm; second lap merged %.2f s after its first pose, "
      "ATE %.2f cm, in the first lap's alignment %.2f cm (%zu frames), %ld points fused\n",
      first.map.keyframes.size(), lap1_m * 100, merge_after_s, lap2_own_m * 100,
      lap2.ape.stats.rmse * 100, lap2.matched.est.poses.size(),
      static_cast<long>(second.counters.points_fused));
}

}  // namespace
}  // namespace hs
