// hs-map-save: asks a running hs-mapper to write its map now (MAP_COMMAND SAVE) and waits for
// its answer, a HEARTBEAT whose message starts "save request <seq>". Exit status 0 when saved,
// 1 when the mapper could not (the reason is printed), 2 when no answer came in time.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <string>

#include "common/config/channels.h"
#include "common/core/monotonic_clock.h"
#include "common/lcm/lcm_connection.h"
#include "hsslam/heartbeat_t.hpp"
#include "hsslam/map_command_t.hpp"

namespace {

struct Answer {
  std::string prefix;
  std::string message;
  bool received = false;
};

void on_heartbeat(const lcm::ReceiveBuffer* rbuf, const std::string&, Answer* answer) {
  hsslam::heartbeat_t hb;
  if (hb.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) return;
  if (hb.message.rfind(answer->prefix, 0) != 0) return;
  answer->message = hb.message;
  answer->received = true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Ask a running hs-mapper to save its map now"};
  std::string path, channels_config, url = hs::default_lcm_url();
  double timeout_s = 60.0;
  app.add_option("path", path,
                 "file to write on the mapper's machine (relative: to this shell's directory)")
      ->required();
  app.add_option("--channels", channels_config, "channel names (config/channels.yaml)");
  app.add_option("--timeout", timeout_s, "seconds to wait for the answer")->capture_default_str();
  app.add_option("--lcm-url", url, "LCM URL ($LCM_DEFAULT_URL or the project default)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    const hs::ChannelNames channels =
        channels_config.empty() ? hs::ChannelNames{} : hs::load_channel_names(channels_config);
    auto lcm = hs::connect_lcm(url);
    hsslam::map_command_t cmd;
    cmd.t_ns = hs::monotonic_ns();
    cmd.seq = cmd.t_ns;  // distinct from any other request's
    cmd.command = hsslam::map_command_t::SAVE;
    cmd.path = std::filesystem::absolute(path).string();
    Answer answer{"save request " + std::to_string(cmd.seq), "", false};
    lcm->subscribeFunction(channels.heartbeat, &on_heartbeat, &answer);
    lcm->publish(channels.map_command, &cmd);
    const int64_t deadline = cmd.t_ns + static_cast<int64_t>(timeout_s * 1e9);
    while (!answer.received && hs::monotonic_ns() < deadline)
      lcm->handleTimeout(
          static_cast<int>(std::max<int64_t>(1, (deadline - hs::monotonic_ns()) / 1'000'000)));
    if (!answer.received) {
      std::fprintf(stderr, "hs-map-save: no answer from hs-mapper on %s within %.0f s\n",
                   channels.heartbeat.c_str(), timeout_s);
      return 2;
    }
    std::printf("%s\n", answer.message.c_str());
    return answer.message.find(": map saved to ") != std::string::npos ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hs-map-save: %s\n", e.what());
    return 1;
  }
}
