// hs-launch: starts and supervises the chosen set of HS-SLAM processes on one machine (for
// development; a vehicle uses the systemd units in config/systemd/).
#include <sys/ioctl.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "common/core/monotonic_clock.h"
#include "common/core/wall_clock.h"
#include "common/lcm/lcm_connection.h"
#include "common/lcm/process_loop.h"
#include "tools/launch/forwarded_signals.h"
#include "tools/launch/launch_options.h"
#include "tools/launch/status_table.h"
#include "tools/launch/supervisor.h"

namespace {

constexpr const char* kFooter = R"(
Starts the config's enabled processes (or those --only names) in order, each in its own process
group with LCM_DEFAULT_URL set and its output in LOG_DIR/NAME.log. Restarts per process policy
(never | on-failure | always) with exponential backoff, gives up after max_failures in a row,
and kills (then restarts) a process whose HEARTBEAT stays silent past its timeout. SIGINT/SIGTERM
stop everything (SIGKILL after each stop timeout; a second one kills at once), as do SIGHUP and
SIGQUIT (with SIGTERM); SIGUSR1 and SIGUSR2 are forwarded. The status shows, per process, its state and what its HEARTBEAT says:
redrawn in place on a terminal, printed every status_log_period_s otherwise. Exit status 1 when a
process was given up or a required one failed.)";

std::string clock_text() {
  return hs::wall_clock_text("%H:%M:%S", hs::TimeZone::kLocal);
}

std::string signal_name(int sig) {
  const char* abbrev = sigabbrev_np(sig);
  return std::string("SIG") + (abbrev ? abbrev : std::to_string(sig).c_str());
}

size_t terminal_width() {
  winsize ws{};
  return ::ioctl(STDOUT_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0 ? ws.ws_col : 160;
}

// The status block on stdout: redrawn in place (live) or printed as a block (log).
class StatusView {
 public:
  explicit StatusView(bool live) : live_(live) {}

  void print_events(const std::vector<std::string>& events) {
    if (events.empty()) return;
    erase();
    for (const std::string& e : events)
      std::printf("hs-launch: %s %s\n", clock_text().c_str(), e.c_str());
    std::fflush(stdout);
  }

  void draw(const hs::Supervisor& sup, int64_t now_ns) {
    erase();
    const std::vector<std::string> lines = hs::format_status(sup.processes(), now_ns);
    const size_t width = live_ ? terminal_width() : std::string::npos;
    if (!live_) std::printf("hs-launch: %s status\n", clock_text().c_str());
    for (const std::string& line : lines)
      std::printf("  %s\n", line.substr(0, width > 2 ? width - 2 : 0).c_str());
    drawn_ = live_ ? lines.size() : 0;
    std::fflush(stdout);
  }

 private:
  void erase() {
    if (drawn_ > 0) std::printf("\033[%zuA\033[J", drawn_);
    drawn_ = 0;
  }

  bool live_;
  size_t drawn_ = 0;
};

hsslam::heartbeat_t own_heartbeat(const hs::Supervisor& sup) {
  bool all_ok = true;
  for (const hs::SupervisedProcess& p : sup.processes())
    all_ok &= p.state == hs::ProcessState::kRunning || p.state == hs::ProcessState::kEnded;
  hsslam::heartbeat_t hb = hs::heartbeat_header(
      "hs-launch", sup.stopping()
                       ? hsslam::heartbeat_t::STOPPING
                       : (all_ok ? hsslam::heartbeat_t::OK : hsslam::heartbeat_t::DEGRADED));
  for (const hs::SupervisedProcess& p : sup.processes()) {
    hb.message += (hb.message.empty() ? "" : ", ") + p.spec.name + " " + hs::to_string(p.state);
    hb.counter_names.push_back(p.spec.name + ".starts");
    hb.counter_values.push_back(p.starts);
  }
  hb.num_counters = static_cast<int32_t>(hb.counter_names.size());
  return hb;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hs-launch: starts and supervises HS-SLAM processes on one machine"};
  app.footer(kFooter);
  std::string config, url, log_dir, status = "auto";
  std::vector<std::string> only;
  app.add_option("config", config, "system config (config/system.yaml)")->required();
  app.add_option("--only", only, "start only these processes (comma-separated config names)")
      ->delimiter(',');
  app.add_option("--lcm-url", url, "LCM URL of hs-launch and every process (overrides the config)");
  app.add_option("--log-dir", log_dir, "directory of the processes' logs (overrides the config)");
  app.add_option("--status", status, "auto (live on a terminal) | live | log | off")
      ->check(CLI::IsMember({"auto", "live", "log", "off"}))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  hs::install_forwarded_signals();
  std::unique_ptr<hs::Supervisor> sup;
  hs::LaunchOptions options;
  try {
    options = hs::load_launch_options(config);
    if (!only.empty()) hs::select_processes(options, only);
    if (!url.empty()) options.lcm_url = url;
    if (options.lcm_url.empty()) options.lcm_url = hs::default_lcm_url();
    if (!log_dir.empty()) options.log_dir = log_dir;
    sup = std::make_unique<hs::Supervisor>(options, hs::self_directory());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hs-launch: error: %s\n", e.what());
    return 2;
  }

  std::unique_ptr<lcm::LCM> lcm;
  try {
    lcm = hs::connect_lcm(options.lcm_url);
    lcm->subscribeFunction(
        options.channels.heartbeat,
        +[](const lcm::ReceiveBuffer*, const std::string&, const hsslam::heartbeat_t* hb,
            hs::Supervisor* s) { s->on_heartbeat(*hb, hs::monotonic_ns()); },
        sup.get());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hs-launch: warning: no HEARTBEAT status or hang detection: %s\n",
                 e.what());
    lcm.reset();
  }

  const bool live = status == "live" || (status == "auto" && ::isatty(STDOUT_FILENO));
  StatusView view(live);
  std::printf("hs-launch: %zu processes on %s, logs in %s/\n", sup->processes().size(),
              options.lcm_url.c_str(), options.log_dir.c_str());
  int64_t now = hs::monotonic_ns();
  sup->start(now);
  int64_t next_status = now, next_heartbeat = now;
  const int64_t status_period = live ? options.status_period_ns : options.status_log_period_ns;
  while (!sup->done()) {
    if (lcm) {
      if (lcm->handleTimeout(100) < 0 && !hs::signal_pending())
        std::fprintf(stderr, "hs-launch: warning: LCM receive failed\n");
    } else {
      ::usleep(100'000);
    }
    now = hs::monotonic_ns();
    for (int sig : hs::take_pending_signals()) {
      const bool forward_only = sig == SIGUSR1 || sig == SIGUSR2;
      if (forward_only) {
        view.print_events({signal_name(sig) + ": forwarded"});
        sup->forward(sig);
      } else if (sup->stopping()) {
        sup->kill_all();
        view.print_events({signal_name(sig) + " while stopping: SIGKILL to all"});
      } else {
        view.print_events({signal_name(sig) + ": stopping all"});
        sup->stop(sig == SIGINT ? SIGINT : SIGTERM, now);
      }
    }
    sup->tick(now);
    view.print_events(sup->take_events());
    if (status != "off" && status_period > 0 && now >= next_status) {
      view.draw(*sup, now);
      next_status = now + status_period;
    }
    if (lcm && now >= next_heartbeat) {
      const hsslam::heartbeat_t hb = own_heartbeat(*sup);
      lcm->publish(options.channels.heartbeat, &hb);
      next_heartbeat = now + options.heartbeat_period_ns;
    }
  }
  if (status != "off") view.draw(*sup, hs::monotonic_ns());
  std::printf("hs-launch: all processes ended (exit status %d)\n", sup->exit_code());
  return sup->exit_code();
}
