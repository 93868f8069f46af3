// hs-logger: records LCM channels into rotating, crash-safe LCM log files (stock lcm-logplayer
// replays them), or checks such files.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "common/core/stop_signal.h"
#include "common/lcm/lcm_connection.h"
#include "common/lcm/process_loop.h"
#include "logger/lcm_log_format.h"
#include "logger/log_manifest.h"
#include "logger/logger_node.h"
#include "logger/logger_options.h"

namespace {

constexpr const char* kFooter = R"(
Records every channel the config's include/exclude regexes keep (default: all) into
DIR/PREFIX-YYYYmmdd-HHMMSS-NNNN.lcmlog, rotated by size and age, each closed file with a
FILE.manifest.json (channels, counts, time span, messages lost upstream by seq gaps). Buffered
events are written and fdatasync'ed every flush period (50 ms by default): a kill -9 or power cut
loses at most that. Below the disk guard's free space it stops (or deletes its own oldest files)
and says so on HEARTBEAT. Stops on SIGINT/SIGTERM after writing what it had already received
(for up to 0.5 s) and closing the file.
--check FILE...: reads log files as a player would, skipping a torn last event (after a crash)
and damaged regions, and prints what they hold as JSON (exit 1 if a file cannot be read).)";

int check_files(const std::vector<std::string>& files) {
  int status = 0;
  for (const std::string& f : files) {
    try {
      const hs::LogScan scan = hs::scan_log_file(f);
      hs::LogManifest manifest;
      for (const hs::LogEvent& e : scan.events)
        manifest.add(e.channel, e.utime, static_cast<int64_t>(e.data.size()),
                     hs::message_seq(e.data.data(), e.data.size()));
      nlohmann::json j = manifest.to_json();
      j["file"] = f;
      j["torn_tail_bytes"] = scan.torn_tail_bytes;
      j["skipped_bytes"] = scan.skipped_bytes;
      j["skipped_regions"] = scan.skipped_regions;
      std::printf("%s\n", j.dump(2).c_str());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "hs-logger: %s\n", e.what());
      status = 1;
    }
  }
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hs-logger: records LCM channels into rotating, crash-safe log files"};
  app.footer(kFooter);
  std::string config, dir, url = hs::default_lcm_url();
  std::vector<std::string> check;
  app.add_option("--config", config, "logger config (config/logger.yaml; default: built in)");
  app.add_option("--dir", dir, "log directory (overrides the config's)");
  app.add_option("--lcm-url", url, "LCM URL ($LCM_DEFAULT_URL or the project default)")
      ->capture_default_str();
  app.add_option("--check", check, "check these log files instead of recording");
  CLI11_PARSE(app, argc, argv);
  if (!check.empty()) return check_files(check);

  hs::install_stop_signals();
  try {
    hs::LoggerOptions options;
    if (!config.empty()) options = hs::load_logger_options(config);
    if (!dir.empty()) options.writer.directory = dir;
    auto lcm = hs::connect_lcm(url);
    if (const std::string w = hs::receive_buffer_warning(url); !w.empty())
      std::fprintf(stderr, "hs-logger: warning: %s\n", w.c_str());
    hs::LoggerNode node(*lcm, options);
    node.start();
    std::printf("hs-logger: recording %s into %s\n", url.c_str(), options.writer.directory.c_str());
    std::fflush(stdout);  // tells a supervising script that the subscription is live
    hs::handle_until_stopped(*lcm, [&] { node.poll(); });
    hs::drain_received(*lcm, 500);
    node.stop();
    const hs::LogWriterStatus& s = node.writer_status();
    std::printf(
        "hs-logger: %lld messages received, %lld filtered out, %lld written (%.1f MB) in %lld "
        "files, %lld dropped, %lld write errors%s%s\n",
        static_cast<long long>(node.counters().received),
        static_cast<long long>(node.counters().filtered_out),
        static_cast<long long>(s.events_written), static_cast<double>(s.bytes_written) / 1e6,
        static_cast<long long>(s.files_closed), static_cast<long long>(s.events_dropped),
        static_cast<long long>(s.write_errors), s.message.empty() ? "" : "; ", s.message.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hs-logger: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
