// hs-euroc2lcm: EuRoC ASL folder -> LCM log with sensor-time event stamps (see --help).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "common/config/channels.h"
#include "common/core/error.h"
#include "common/core/types.h"
#include "common/dataset/euroc_reader.h"
#include "common/lcm/dataset_log.h"

namespace {

constexpr const char* kFooter = R"(
The log holds stereo_frame_t on CAM_STEREO, imu_batch_t on IMU and ground_truth_t on
GROUND_TRUTH (names from --config). Event timestamps are the sensor times, so stock
lcm-logplayer replays with sensor-time spacing, e.g.:
  lcm-logplayer -l 'udpm://239.255.76.67:7667?ttl=0' FILE.lcmlog
cam0/cam1 rows without a partner of the same timestamp are dropped and listed; every other
defect (bad CSV row, non-increasing time, missing or bad image) stops with file:line.
Exit status: 0 on success, 1 on bad input (nothing is written).)";

void print_summary(const hs::EurocReader& reader, const hs::DatasetLogSummary& s,
                   const std::string& out) {
  std::printf(
      "wrote %s: %lld frames (%s), %lld IMU samples in %lld messages, %lld ground-truth"
      " states, %.1f MB, sensor time %.3f .. %.3f s (%.3f s)\n",
      out.c_str(), static_cast<long long>(s.frames), reader.stereo() ? "stereo" : "mono",
      static_cast<long long>(s.imu_samples), static_cast<long long>(s.imu_messages),
      static_cast<long long>(s.ground_truth), static_cast<double>(s.bytes) / 1e6,
      hs::ns_to_s(s.first_t_ns), hs::ns_to_s(s.last_t_ns), hs::ns_to_s(s.last_t_ns - s.first_t_ns));
  const auto& dropped = reader.dropped();
  std::printf("dropped: %zu camera rows without a partner of equal timestamp\n", dropped.size());
  constexpr size_t kShown = 20;
  for (size_t i = 0; i < dropped.size() && i < kShown; ++i)
    std::printf("  %s\n", dropped[i].c_str());
  if (dropped.size() > kShown) std::printf("  ... and %zu more\n", dropped.size() - kShown);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hs-euroc2lcm: convert a EuRoC ASL dataset folder into an LCM log file"};
  app.footer(kFooter);
  std::string dataset, out, encoding = "mono8", config;
  bool no_ground_truth = false, mono = false;
  hs::DatasetLogOptions options;
  app.add_option("--dataset", dataset, "dataset root (containing mav0/) or mav0/ itself")
      ->required();
  app.add_option("--out", out, "output LCM log file")->required();
  app.add_option("--encoding", encoding, "image encoding: mono8 (raw) or png (lossless)")
      ->check(CLI::IsMember({"mono8", "png"}))
      ->capture_default_str();
  app.add_option("--imu-batch", options.imu_batch,
                 "most IMU samples per message; a batch is also sent before every frame")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--config", config, "YAML file with a channels: section (config/channels.yaml)");
  app.add_flag("--no-ground-truth", no_ground_truth, "do not write GROUND_TRUTH");
  app.add_flag("--mono", mono, "use cam0 only, even when cam1 exists");
  CLI11_PARSE(app, argc, argv);

  try {
    if (!config.empty()) options.channels = hs::load_channel_names(config);
    options.encoding = hs::parse_image_encoding(encoding);
    hs::EurocOptions reader_options;
    reader_options.use_cam1 = !mono;
    reader_options.use_ground_truth = !no_ground_truth;
    const hs::EurocReader reader(dataset, reader_options);
    const std::string gt_text = no_ground_truth ? "off (--no-ground-truth)"
                                : reader.has_ground_truth_folder()
                                    ? std::to_string(reader.ground_truth().size()) + " states"
                                    : "none (no state_groundtruth_estimate0/)";
    std::printf("%s: %zu %s frames %dx%d, %zu IMU samples, ground truth: %s\n",
                reader.mav0().c_str(), reader.frames().size(), reader.stereo() ? "stereo" : "mono",
                reader.image_size().width, reader.image_size().height, reader.imu().size(),
                gt_text.c_str());
    size_t last_decile = 0;
    const hs::DatasetLogSummary summary =
        hs::write_dataset_log(reader, options, out, [&](size_t done, size_t total) {
          const size_t decile = done * 10 / total;
          if (decile == last_decile) return;
          last_decile = decile;
          std::fprintf(stderr, "[hs-euroc2lcm] %3zu%% of %zu events\n", decile * 10, total);
        });
    print_summary(reader, summary, out);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hs-euroc2lcm: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
