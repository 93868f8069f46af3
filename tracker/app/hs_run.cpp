// hs-run: the tracker over a dataset in one process (deterministic, as fast as possible).
//   hs-run --dataset DIR [--config config/euroc.yaml] [--out DIR]
//   hs-run --sim config/sim/room_mav.yaml [--duration S] [--seed N]
//   ... --with-mapper: the mapper in the same process, each keyframe's correction applied before
//   the next frame (deterministic: the tracker waits for the mapper)
// Writes the TUM trajectory, a per-frame timing CSV, and, with ground truth, an hs-eval summary
// (text, JSON, PNG plot).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <vector>

#include "common/core/error.h"
#include "common/eval/plot.h"
#include "mapper/mapper.h"
#include "mapper/mapper_options.h"
#include "mapper/offline/mapper_report.h"
#include "tracker/offline/offline_run.h"
#include "tracker/offline/run_report.h"

int main(int argc, char** argv) {
  CLI::App app{"Run the HS-SLAM tracker over a dataset in process"};
  std::string dataset, sim_path, config, mapper_config, out_dir = "out/run", descriptors;
  std::string load_map, save_map;
  double duration_s = 0.0, skip_s = 0.0;
  int64_t seed = -1;
  bool mono = false, verbose = false, with_mapper = false;
  auto* ds = app.add_option("--dataset", dataset, "EuRoC folder (root or mav0/)");
  app.add_option("--sim", sim_path, "simulate this scenario in memory instead")->excludes(ds);
  app.add_option("--duration", duration_s, "with --sim: override the duration (s)");
  app.add_option("--seed", seed, "with --sim: override the seed");
  app.add_option("--skip", skip_s, "start the tracker this many seconds into the dataset (s)");
  app.add_option("--config", config, "tracker config (default: built-in EuRoC settings)");
  app.add_option("--descriptors", descriptors, "hybrid | every-frame (overrides the config)");
  app.add_flag("--mono", mono, "use cam0 only");
  app.add_flag("--with-mapper", with_mapper,
               "run the mapper in process; the tracker waits for each correction");
  app.add_option("--mapper-config", mapper_config, "mapper config (default: built-in settings)");
  app.add_option("--load-map", load_map, "with --with-mapper: start the mapper from this map file");
  app.add_option("--save-map", save_map,
                 "with --with-mapper: write the mapper's map here at the end");
  bool localise = false;
  app.add_flag("--localisation-only", localise,
               "with --load-map: the mapper localises in the loaded map, does not extend it");
  app.add_option("--out", out_dir, "output folder")->capture_default_str();
  app.add_flag("-v,--verbose", verbose, "print every tracker message");
  CLI11_PARSE(app, argc, argv);
  if (dataset.empty() && sim_path.empty()) {
    std::cerr << "hs-run: give --dataset DIR or --sim SCENARIO.yaml\n";
    return 2;
  }
  try {
    hs::TrackerOptions options =
        config.empty() ? hs::TrackerOptions{} : hs::load_tracker_options(config);
    if (!descriptors.empty()) {
      if (descriptors != "hybrid" && descriptors != "every-frame")
        throw hs::InputError("--descriptors must be hybrid or every-frame");
      options.descriptors =
          descriptors == "hybrid" ? hs::DescriptorMode::kHybrid : hs::DescriptorMode::kEveryFrame;
    }
    if (mono) options.stereo = false;
    hs::OfflineRunOptions run_options;
    run_options.progress = true;
    run_options.verbose = verbose;
    run_options.skip_ns = hs::s_to_ns(skip_s);
    std::optional<hs::EurocReader> reader;
    std::optional<hs::EurocStream> stream;
    std::optional<hs::sim::DatasetGenerator> gen;
    hs::EventSource source;
    if (!dataset.empty()) {
      hs::EurocOptions euroc;
      euroc.use_cam1 = !mono;
      reader.emplace(dataset, euroc);
      if (!reader->stereo()) options.stereo = false;  // a mono rig's dataset (no cam1)
      if (config.empty()) options.calib = hs::read_stereo_calib(reader->mav0());
      stream.emplace(*reader);
      std::cerr << "hs-run: " << reader->frames().size() << " frames from " << reader->mav0()
                << "\n";
      source = hs::euroc_source(*stream);
    } else {
      hs::sim::Scenario scenario = hs::sim::load_scenario(sim_path);
      if (duration_s > 0) scenario.duration_s = duration_s;
      if (seed >= 0) scenario.seed = static_cast<uint64_t>(seed);
      options.calib = scenario.camera.calib;
      gen.emplace(scenario);
      std::cerr << "hs-run: simulating " << scenario.name << ", " << gen->num_frames()
                << " frames\n";
      source = hs::sim_source(*gen, options.stereo);
    }
    std::optional<hs::Mapper> mapper;
    hs::MapperRunStats mapper_stats;
    if (with_mapper) {
      // The rig is the tracker's (from its config, the dataset or the simulator).
      hs::MapperOptions mapper_options = mapper_config.empty()
                                             ? hs::MapperOptions{}
                                             : hs::load_mapper_config(mapper_config).mapper;
      mapper_options.window.imu = options.imu;
      if (localise && load_map.empty())
        throw hs::InputError("--localisation-only", "needs a map to localise in (--load-map)");
      mapper_options.localisation_only = mapper_options.localisation_only || localise;
      // Reproducible: the tracker waits for each bundle adjustment to finish, however long.
      mapper.emplace(options.calib, hs::reproducible(mapper_options));
      if (!load_map.empty()) mapper->load(hs::read_map_file(load_map));
      run_options.back_end = hs::in_process_back_end(*mapper, mapper_stats, verbose);
      run_options.atlas = hs::in_process_atlas(*mapper);
    }
    const hs::OfflineRunResult result = hs::run_offline(options, source, run_options);
    std::filesystem::create_directories(out_dir);
    std::cout << hs::write_run_outputs(out_dir, result);
    if (mapper) {
      hs::finish_back_end(*mapper, mapper_stats);
      hs::write_loops_csv(out_dir + "/loops.csv", mapper_stats);
      std::cout << hs::mapper_text(mapper_stats, *mapper, result);
      std::cout << hs::final_trajectory_text(out_dir, result, *mapper);
      if (!save_map.empty()) {
        hs::write_map_file(save_map, mapper->map_file());
        std::cout << "map saved to " << save_map << "\n";
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "hs-run: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
