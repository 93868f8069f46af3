// hs-bench-loop [--sim config/sim/X.yaml] [--duration S]: what the back end's loop machinery costs
// (issue 7), on a simulated drive with the tracker and the mapper in one process (reproducible, as
// hs-run --with-mapper): loop detection per keyframe (place index query and geometric
// verification), the pose graph per loop closed, the full BA after it, and the saved map's size per
// keyframe. Each time is also given as a ratio to the local BA's median in the same run, the
// mapper's cost per keyframe.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "common/sim/scenario.h"
#include "mapper/mapper_options.h"
#include "mapper/offline/mapper_report.h"
#include "tracker/offline/run_report.h"

namespace {

void line(const char* what, const hs::TimeStats& t, double baseline_ms) {
  std::printf("  %-34s %6zu x  median %8.2f ms  p95 %8.2f ms  max %8.2f ms  (%.2fx local BA)\n",
              what, t.count, t.median, t.p95, t.max,
              baseline_ms > 0 ? t.median / baseline_ms : 0.0);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Loop detection, pose graph, full BA and map file size on a simulated drive."};
  std::string sim_path = "config/sim/vehicle_loop.yaml";
  std::string mapper_config;
  double duration_s = 0.0;
  app.add_option("--sim", sim_path,
                 "scenario (default: vehicle_loop, a block driven twice; run from the repository)")
      ->check(CLI::ExistingFile);
  app.add_option("--mapper-config", mapper_config, "mapper config (default: built-in settings)")
      ->check(CLI::ExistingFile);
  app.add_option("--duration", duration_s, "seconds of the scenario (default: all of it)");
  CLI11_PARSE(app, argc, argv);

  try {
    hs::sim::Scenario scenario = hs::sim::load_scenario(sim_path);
    if (duration_s > 0) scenario.duration_s = duration_s;
    hs::TrackerOptions options;
    options.calib = scenario.camera.calib;
    hs::MapperOptions mapper_options =
        mapper_config.empty() ? hs::MapperOptions{} : hs::load_mapper_config(mapper_config).mapper;
    mapper_options.window.imu = options.imu;
    mapper_options.full_ba.enabled = true;  // its cost is one of the figures
    hs::Mapper mapper(options.calib, hs::reproducible(mapper_options));
    hs::MapperRunStats stats;
    hs::OfflineRunOptions run_options;
    run_options.back_end = hs::in_process_back_end(mapper, stats);
    run_options.progress = true;
    hs::sim::DatasetGenerator generator(scenario);
    std::cerr << "hs-bench-loop: " << scenario.duration_s << " s of " << sim_path << "\n";
    const hs::OfflineRunResult result =
        hs::run_offline(options, hs::sim_source(generator), run_options);
    hs::finish_back_end(mapper, stats);

    const std::string path =
        (std::filesystem::temp_directory_path() / "hs_bench_loop.hsmap").string();
    const hs::MapFile map = mapper.map_file();
    hs::write_map_file(path, map);
    const auto bytes = std::filesystem::file_size(path);
    std::filesystem::remove(path);

    const hs::MapperCounters& c = mapper.counters();
    const hs::TimeStats ba = hs::time_stats(stats.ba_ms);
    const size_t keyframes = mapper.graph().num_keyframes();
    std::printf("%zu frames, %ld keyframes mapped, %zu in the map, %zu points\n",
                result.frames.size(), static_cast<long>(c.keyframes), keyframes,
                mapper.graph().num_points());
    std::printf("baseline: tracking per frame median %.2f ms; local BA per keyframe:\n",
                hs::summarise_timing(result).all.median);
    line("local BA", ba, ba.median);
    line("loop detection (query + verify)", hs::time_stats(stats.loop_query_ms), ba.median);
    line("pose graph (per loop closed)", hs::time_stats(stats.pose_graph_ms), ba.median);
    line("full BA (its own thread)", hs::time_stats(stats.full_ba_ms), ba.median);
    std::printf("  full BA problem: %.0f keyframes, %.0f points (mean)\n",
                stats.full_ba_keyframes.empty() ? 0.0 : stats.full_ba_keyframes.front(),
                stats.full_ba_points.empty() ? 0.0 : stats.full_ba_points.front());
    std::printf(
        "  loops: %ld detected, %ld closed, %ld maps merged; full BAs %ld (%ld discarded)\n",
        static_cast<long>(c.loops_detected), static_cast<long>(c.loops_closed),
        static_cast<long>(c.maps_merged), static_cast<long>(c.full_bas),
        static_cast<long>(c.full_bas_discarded));
    std::printf(
        "map file: %zu keyframes, %.2f MB, %.1f kB per keyframe; place index %.1f kB per "
        "keyframe in memory\n",
        map.keyframes.size(), bytes / 1e6, bytes / 1e3 / std::max<size_t>(1, map.keyframes.size()),
        mapper.loop_index_bytes() / 1e3 / std::max<size_t>(1, keyframes));
  } catch (const std::exception& e) {
    std::cerr << "hs-bench-loop: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
