// hs-bench-tracker: the paper's Table 4 on one sequence. Runs the tracker in hybrid mode (ORB
// only at keyframes) and in every-frame mode (the ORB-SLAM3-like baseline) one after the other,
// each in its own child process streaming the same EuRoC folder from disk, and prints per-frame
// tracking times side by side, keyframe / non-keyframe times, ATE, peak RSS and the targets.
//   hs-bench-tracker --sim config/sim/room_mav.yaml [--duration S] [--seed N] [--json FILE]
//   hs-bench-tracker --dataset EUROC_DIR [--config config/euroc.yaml] [--json FILE]
// With --mono it also runs hybrid on cam0 alone (the mono-inertial rig) and compares it with
// the stereo hybrid run.
// A simulated sequence is first written to a temporary EuRoC folder (removed at the end), so
// both modes read identical frames and rendering is in neither mode's time nor memory.
// Times are wall-clock per frame as the tracker reports them: run on an otherwise idle machine.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "common/core/atomic_file.h"
#include "common/core/error.h"
#include "common/sim/euroc_writer.h"
#include "tools/bench_tracker/child_process.h"
#include "tracker/offline/offline_run.h"
#include "tracker/offline/run_report.h"

namespace {

// A fresh directory under the system temp dir, removed with its contents on destruction.
class TempDir {
 public:
  TempDir() {
    std::string tmpl = (std::filesystem::temp_directory_path() / "hs-bench-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("cannot create a directory " + tmpl);
    path_ = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// Writes the scenario as an EuRoC folder `dir` in a child process (the renderer's memory stays
// out of the parent, whose pages every later child starts with).
void write_sim_dataset(const hs::sim::Scenario& scenario, const std::string& dir) {
  hs::run_in_child("simulation", [&] {
    hs::sim::DatasetGenerator gen(scenario);
    std::fprintf(stderr, "hs-bench-tracker: writing %zu simulated frames to %s\n", gen.num_frames(),
                 dir.c_str());
    hs::sim::EurocWriteOptions options;
    options.progress = [](size_t done, size_t total) {
      if (done % 200 == 0 || done == total) std::fprintf(stderr, "  %zu/%zu frames\n", done, total);
    };
    hs::sim::write_euroc(gen, dir, options);
    return std::string();
  });
}

hs::ModeReport run_mode(hs::TrackerOptions options, hs::DescriptorMode mode,
                        const std::string& dataset_dir, bool calib_from_dataset,
                        bool mono = false) {
  const std::string name =
      std::string(mode == hs::DescriptorMode::kHybrid ? "hybrid" : "every-frame") +
      (mono ? " mono" : "");
  options.descriptors = mode;
  if (mono) options.stereo = false;
  std::fprintf(stderr, "hs-bench-tracker: %s on %s\n", name.c_str(), dataset_dir.c_str());
  const hs::ChildResult child = hs::run_in_child(name + " run", [&] {
    const hs::EurocReader reader(dataset_dir);
    if (calib_from_dataset) options.calib = hs::read_stereo_calib(reader.mav0());
    hs::EurocStream stream(reader);
    hs::OfflineRunOptions run_options;
    run_options.progress = true;
    const hs::OfflineRunResult result =
        hs::run_offline(options, hs::euroc_source(stream), run_options);
    return to_json(hs::mode_report(name, result)).dump();
  });
  hs::ModeReport report = hs::mode_report_from_json(nlohmann::json::parse(child.output));
  report.peak_rss_mb = child.peak_rss_mb;
  report.cpu_s = child.cpu_s;
  return report;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Tracker benchmark: hybrid vs every-frame descriptors (the paper's Table 4)"};
  std::string dataset, sim_path, config, json_path;
  double duration_s = 0.0;
  int64_t seed = -1;
  auto* ds = app.add_option("--dataset", dataset, "EuRoC folder (root or mav0/)");
  app.add_option("--sim", sim_path, "simulate this scenario (written to a temporary folder)")
      ->excludes(ds)
      ->check(CLI::ExistingFile);
  app.add_option("--duration", duration_s, "with --sim: override the duration (s)")
      ->check(CLI::PositiveNumber);
  app.add_option("--seed", seed, "with --sim: override the seed")->check(CLI::NonNegativeNumber);
  app.add_option("--config", config, "tracker config (default: built-in EuRoC settings)")
      ->check(CLI::ExistingFile);
  app.add_option("--json", json_path, "also write the figures as JSON");
  bool with_mono = false;
  app.add_flag("--mono", with_mono, "also run hybrid on cam0 alone and compare mono with stereo");
  CLI11_PARSE(app, argc, argv);
  if (dataset.empty() && sim_path.empty()) {
    std::cerr << "hs-bench-tracker: give --dataset DIR or --sim SCENARIO.yaml\n";
    return 2;
  }
  try {
    const hs::TrackerOptions options =
        config.empty() ? hs::TrackerOptions{} : hs::load_tracker_options(config);
    // As hs-run: the dataset's sensor.yaml calibration unless a config is given; a simulated
    // sequence always brings its own.
    const bool calib_from_dataset = config.empty() || !sim_path.empty();
    std::string sequence = dataset;
    std::optional<TempDir> tmp;
    if (!sim_path.empty()) {
      hs::sim::Scenario scenario = hs::sim::load_scenario(sim_path);
      if (duration_s > 0) scenario.duration_s = duration_s;
      if (seed >= 0) scenario.seed = static_cast<uint64_t>(seed);
      tmp.emplace();
      dataset = tmp->path() + "/" + scenario.name;
      write_sim_dataset(scenario, dataset);
      std::ostringstream name;
      name << "simulated " << scenario.name << ", " << scenario.duration_s << " s, seed "
           << scenario.seed;
      sequence = name.str();
    }
    const double baseline_rss_mb = hs::self_peak_rss_mb();
    const hs::ModeReport hybrid =
        run_mode(options, hs::DescriptorMode::kHybrid, dataset, calib_from_dataset);
    std::optional<hs::ModeReport> mono;
    if (with_mono)
      mono = run_mode(options, hs::DescriptorMode::kHybrid, dataset, calib_from_dataset, true);
    const hs::ModeReport every_frame =
        run_mode(options, hs::DescriptorMode::kEveryFrame, dataset, calib_from_dataset);
    const std::vector<hs::TargetCheck> checks = hs::check_targets(hybrid, every_frame);

    std::printf("tracker benchmark: %s\n", sequence.c_str());
    std::printf(
        "wall-clock tracking time per frame; one process per mode, one after the other; for "
        "scale, the bench process alone (program and libraries) peaks at %.1f MB\n\n",
        baseline_rss_mb);
    std::printf("%s", hs::comparison_text(hybrid, every_frame, checks).c_str());
    if (mono) std::printf("\n%s", hs::rig_comparison_text(hybrid, *mono).c_str());
    if (!json_path.empty()) {
      nlohmann::json j = hs::comparison_json(hybrid, every_frame, checks);
      j["sequence"] = sequence;
      j["baseline_rss_mb"] = baseline_rss_mb;
      if (mono) j["mono"] = to_json(*mono);
      hs::write_file_atomically(json_path, j.dump(2) + "\n");
    }
  } catch (const std::exception& e) {
    std::cerr << "hs-bench-tracker: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
