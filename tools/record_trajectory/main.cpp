// hs-record-trajectory: record the poses of one LCM channel into a TUM file (see --help).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

#include "common/core/stop_signal.h"
#include "common/lcm/lcm_connection.h"
#include "common/lcm/pose_recorder.h"

namespace {

constexpr const char* kFooter = R"(
The channel's messages must be hsslam.odometry_t or hsslam.ground_truth_t (told apart by
fingerprint). Recording stops on SIGINT/SIGTERM, after --count poses, or when no pose has
arrived for --idle-timeout seconds (counted from start until the first pose). The TUM file
("t[s] x y z qx qy qz qw", body in world, time order) is written atomically at exit, with a
count of the messages heard on every channel. Demo:
  hs-record-trajectory --channel GROUND_TRUTH --out gt.tum --idle-timeout 3 &
  lcm-logplayer V1_01.lcmlog     # LCM's default URL: same multicast group and port
Exit status: 0 when the file was written, 1 on errors or when no pose arrived.)";

// A plain function, not a member handler: GCC 12's UBSan vptr check miscompiles LCM's
// pointer-to-member dispatch (the sanitizer CI job crashes with lcm::LCM::subscribe).
void on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                hs::PoseRecorder* recorder) {
  recorder->handle(channel, rbuf->data, rbuf->data_size);
}

void print_report(const hs::PoseRecorder& recorder) {
  std::printf("messages heard per channel:\n");
  for (const auto& [channel, n] : recorder.counts())
    std::printf("  %-20s %lld\n", channel.c_str(), static_cast<long long>(n));
  if (recorder.rejected() > 0)
    std::printf("rejected %lld messages on %s; first: %s\n",
                static_cast<long long>(recorder.rejected()), recorder.channel().c_str(),
                recorder.first_error().c_str());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hs-record-trajectory: record poses from an LCM channel into a TUM file"};
  app.footer(kFooter);
  std::string channel, out, url = hs::default_lcm_url();
  long long count = 0;
  double idle_timeout_s = 0.0;
  app.add_option("--channel", channel, "channel with odometry_t or ground_truth_t, e.g. POSE")
      ->required();
  app.add_option("--out", out, "output TUM trajectory file")->required();
  app.add_option("--lcm-url", url, "LCM URL ($LCM_DEFAULT_URL or the project default)")
      ->capture_default_str();
  app.add_option("--count", count, "stop after this many poses (0: no limit)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--idle-timeout", idle_timeout_s,
                 "stop after this many seconds without a pose (0: never)")
      ->check(CLI::NonNegativeNumber);
  CLI11_PARSE(app, argc, argv);

  hs::install_stop_signals();

  try {
    const std::string warning = hs::receive_buffer_warning(url);
    if (!warning.empty())
      std::fprintf(stderr, "hs-record-trajectory: warning: %s\n", warning.c_str());
    auto lcm = hs::connect_lcm(url);
    hs::PoseRecorder recorder(channel);
    lcm->subscribeFunction(".*", &on_message, &recorder);
    std::printf("recording %s from %s\n", channel.c_str(), url.c_str());
    std::fflush(stdout);  // tells a supervising script that the subscription is live

    using Clock = std::chrono::steady_clock;
    auto last_pose = Clock::now();
    size_t poses_seen = 0;
    while (!hs::stop_requested()) {
      if (lcm->handleTimeout(100) < 0 && !hs::stop_requested())
        throw std::runtime_error("LCM receive failed");
      if (recorder.poses().size() != poses_seen) {
        poses_seen = recorder.poses().size();
        last_pose = Clock::now();
      }
      if (count > 0 && static_cast<long long>(poses_seen) >= count) break;
      const std::chrono::duration<double> idle = Clock::now() - last_pose;
      if (idle_timeout_s > 0 && idle.count() >= idle_timeout_s) break;
    }

    print_report(recorder);
    if (recorder.poses().empty()) {
      std::fprintf(stderr, "hs-record-trajectory: error: no pose received on %s; nothing written\n",
                   channel.c_str());
      return 1;
    }
    const size_t out_of_order = recorder.write_tum(out);
    const std::string note =
        out_of_order ? " (" + std::to_string(out_of_order) + " arrived out of order: sorted)" : "";
    std::printf("wrote %zu %s poses to %s%s\n", recorder.poses().size(),
                recorder.type_name().c_str(), out.c_str(), note.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hs-record-trajectory: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
