// hs-sim: generates a synthetic stereo-inertial dataset with exact ground truth in the EuRoC
// layout from a scenario file (config/sim/*.yaml):
//   hs-sim --scenario config/sim/room_mav.yaml --out /data/sim/room_mav [--seed N] [--duration S]
// The seed drives the furniture/building layout, IMU noise and image noise; the same scenario
// and seed give byte-identical output. DIR appears only once complete.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>

#include "common/core/error.h"
#include "common/sim/dataset_gen.h"
#include "common/sim/euroc_writer.h"
#include "common/sim/scenario.h"

int main(int argc, char** argv) {
  CLI::App app{"Generate a synthetic stereo-inertial dataset (EuRoC layout) from a scenario"};
  std::string scenario_path, out_dir;
  std::optional<int64_t> seed;
  std::optional<double> duration_s;
  hs::sim::EurocWriteOptions write_options;
  bool quiet = false;
  app.add_option("--scenario", scenario_path, "scenario YAML (config/sim/*.yaml)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--out", out_dir, "output directory (gets mav0/...)")->required();
  app.add_option("--seed", seed, "override the scenario seed")->check(CLI::NonNegativeNumber);
  app.add_option("--duration", duration_s, "override the duration, seconds")
      ->check(CLI::PositiveNumber);
  app.add_option("--png-compression", write_options.png_compression, "zlib level 0-9")
      ->check(CLI::Range(0, 9));
  app.add_flag("--overwrite", write_options.overwrite, "replace an existing output directory");
  app.add_flag("--quiet", quiet, "no progress output");
  CLI11_PARSE(app, argc, argv);

  try {
    hs::sim::Scenario scenario = hs::sim::load_scenario(scenario_path);
    if (seed) scenario.seed = static_cast<uint64_t>(*seed);
    if (duration_s) scenario.duration_s = *duration_s;
    const auto start = std::chrono::steady_clock::now();
    const auto elapsed = [&] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    hs::sim::DatasetGenerator generator(scenario);
    if (!quiet) {
      std::fprintf(stderr,
                   "[hs-sim] %s: seed %llu, %.1f s, %zu stereo frames, %zu IMU samples, %zu quads "
                   "(setup %.1f s)\n",
                   scenario.name.c_str(), static_cast<unsigned long long>(scenario.seed),
                   scenario.duration_s, generator.num_frames(), generator.imu().samples.size(),
                   generator.world().quads.size(), elapsed());
      write_options.progress = [&, last = -1.0](size_t done, size_t total) mutable {
        const double t = elapsed();
        if (done != total && t - last < 2.0) return;
        last = t;
        std::fprintf(stderr, "[hs-sim] frame %zu/%zu, %.1f s elapsed\n", done, total, t);
      };
    }
    hs::sim::write_euroc(generator, out_dir, write_options);
    if (!quiet)
      std::fprintf(stderr, "[hs-sim] wrote %s in %.1f s (%.1f stereo frames/s)\n", out_dir.c_str(),
                   elapsed(), static_cast<double>(generator.num_frames()) / elapsed());
  } catch (const hs::InputError& e) {
    std::cerr << "hs-sim: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
