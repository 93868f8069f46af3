// hs-mapper: the HS-SLAM mapper (local visual-inertial bundle adjustment) as an LCM process.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <exception>
#include <string>

#include "common/core/error.h"
#include "common/core/stop_signal.h"
#include "common/lcm/lcm_connection.h"
#include "common/lcm/process_loop.h"
#include "common/sim/rig_calib_option.h"
#include "mapper/mapper_options.h"
#include "mapper/node/mapper_node.h"

namespace {

constexpr const char* kFooter = R"(
Subscribes to KEYFRAME (keyframe_t from hs-tracker); per keyframe runs a local visual-inertial
bundle adjustment over its covisible window and publishes MAP_UPDATE (map_update_t), which
hs-tracker applies; HEARTBEAT about once a second (backlog and counters). Calibration: the
config's, replaced by --calib (a EuRoC folder's cam0/cam1 sensor.yaml) or --calib-from-sim.
Killed or restarted at any time: the tracker goes on alone and takes the corrections of a new
mapper as they come (it rebuilds its graph from the keyframes that follow).
Stops on SIGINT/SIGTERM after mapping the keyframes already queued, and prints a summary.
--load-map starts from a map saved by --save-map (a world of its own; the tracker's new
keyframes start another); --save-map writes the map when the mapper stops (versioned and
checksummed: a truncated or corrupt file is refused with the reason).
Exit status: 0 after a clean stop, 1 on bad configuration, a bad map file or LCM errors.)";

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hs-mapper: the HS-SLAM mapper as an LCM process"};
  app.footer(kFooter);
  std::string config, calib_dir, sim_scenario, load_map, save_map, url = hs::default_lcm_url();
  app.add_option("--config", config, "mapper config (config/mapper.yaml; default: built in)");
  hs::add_rig_calib_options(app, calib_dir, sim_scenario);
  app.add_option("--load-map", load_map, "start from this map file");
  app.add_option("--save-map", save_map, "write the map here when stopping");
  bool localise = false;
  app.add_flag("--localisation-only", localise,
               "with --load-map: localise in the loaded map, do not extend it");
  app.add_option("--lcm-url", url, "LCM URL ($LCM_DEFAULT_URL or the project default)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  hs::install_stop_signals();
  try {
    hs::MapperConfig c = config.empty() ? hs::MapperConfig{} : hs::load_mapper_config(config);
    hs::override_rig_calib(calib_dir, sim_scenario, c.calib);
    if (localise && load_map.empty())
      throw hs::InputError("--localisation-only", "needs a map to localise in (--load-map)");
    c.mapper.localisation_only = c.mapper.localisation_only || localise;
    auto lcm = hs::connect_lcm(url);
    const auto start = std::chrono::steady_clock::now();
    hs::MapperNode node(*lcm, c.calib, c.mapper, {c.channels, c.heartbeat_period_ns});
    if (!load_map.empty()) {
      const hs::MapFile map = hs::read_map_file(load_map);
      node.load_map(map);
      std::printf("hs-mapper: loaded %zu keyframes, %zu loops from %s\n", map.keyframes.size(),
                  map.loops.size(), load_map.c_str());
    }
    node.start();
    std::printf("hs-mapper: listening on %s (%s)\n", url.c_str(), c.channels.keyframe.c_str());
    std::fflush(stdout);  // tells a supervising script that the subscription is live
    hs::handle_until_stopped(*lcm, [&] { node.poll(); });
    node.stop();
    const hs::MapperNodeStats s = node.stats();
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf(
        "hs-mapper: %lld keyframes received (%lld bad), %lld mapped, %lld MAP_UPDATE; backlog at "
        "most %zu; mapping %.1f ms/keyframe over %.1f s\n",
        static_cast<long long>(s.keyframes_received),
        static_cast<long long>(s.bad_keyframe_messages), static_cast<long long>(s.keyframes_mapped),
        static_cast<long long>(s.updates_published), s.max_backlog,
        s.keyframes_mapped ? s.mapping_ms / s.keyframes_mapped : 0.0, wall_s);
    if (!save_map.empty()) {
      const hs::MapFile map = node.map_file();
      hs::write_map_file(save_map, map);
      std::printf("hs-mapper: saved %zu keyframes to %s\n", map.keyframes.size(), save_map.c_str());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hs-mapper: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
