// hs-trigger: drives the cameras' external-trigger input from a GPIO line (libgpiod) and
// publishes each pulse on TRIGGER with the kernel's edge time.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <sstream>
#include <string>

#include "common/core/stop_signal.h"
#include "common/lcm/lcm_connection.h"
#include "drivers/trigger/trigger_node.h"
#include "drivers/trigger/trigger_options.h"

int main(int argc, char** argv) {
  CLI::App app{"hs-trigger: camera trigger pulses on a GPIO line, published on TRIGGER"};
  app.footer(R"(
Pulses at rate_hz on absolute CLOCK_MONOTONIC deadlines (a deadline missed by a whole period is
skipped and counted). With edge_line set (the trigger looped back to an input, or the cameras'
strobe), each pulse's time is the kernel's timestamp of its rising edge; without, the time just
before the line was set. Stops on SIGINT/SIGTERM with the line low.)");
  std::string config, url = hs::default_lcm_url();
  app.add_option("--config", config, "trigger config (config/trigger.yaml; default: built in)");
  app.add_option("--lcm-url", url, "LCM URL ($LCM_DEFAULT_URL or the project default)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  hs::install_stop_signals();
  try {
    hs::TriggerOptions options;
    if (!config.empty()) options = hs::load_trigger_options(config);
    auto lcm = hs::connect_lcm(url);
    hs::TriggerNode node(*lcm, options);
    const std::string timing = options.sync_line.empty()
                                   ? "at " + (std::ostringstream() << options.rate_hz).str() + " Hz"
                                   : "on every " + std::to_string(options.sync_divider) +
                                         "th edge of " + options.sync_line;
    std::printf("hs-trigger: %s line %s %s%s, publishing %s on %s\n", options.chip.c_str(),
                options.output_line.c_str(), timing.c_str(),
                options.edge_line.empty() ? "" : (", edges on line " + options.edge_line).c_str(),
                options.channels.trigger.c_str(), url.c_str());
    std::fflush(stdout);
    node.run();
    const hs::TriggerStats& s = node.stats();
    std::printf(
        "hs-trigger: %lld pulses, %lld timed by their edge (max delay %.2f ms), %lld "
        "edges missing, %lld deadlines skipped; %lld data-ready edges, %lld stalls, %lld late "
        "pulses (max delay %.2f ms)\n",
        static_cast<long long>(s.pulses), static_cast<long long>(s.edges), s.max_edge_delay_ms,
        static_cast<long long>(s.missing_edges), static_cast<long long>(s.skipped),
        static_cast<long long>(s.sync_edges), static_cast<long long>(s.sync_timeouts),
        static_cast<long long>(s.late_pulses), s.max_sync_delay_ms);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hs-trigger: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
