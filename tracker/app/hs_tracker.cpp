// hs-tracker: the HS-SLAM tracker as an LCM process (see --help).
#include <sys/resource.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <exception>
#include <string>

#include "common/calib/camera_calib.h"
#include "common/core/stop_signal.h"
#include "common/lcm/lcm_connection.h"
#include "common/lcm/process_loop.h"
#include "common/sim/rig_calib_option.h"
#include "tracker/node/tracker_node.h"

namespace {

constexpr const char* kFooter = R"(
Subscribes to CAM_STEREO (stereo_frame_t), IMU (imu_batch_t) and MAP_UPDATE (map_update_t
from a mapper, applied between frames); publishes TRACKER_STATUS per frame, POSE per frame with a state (not while initialising), KEYFRAME per keyframe, POSE_IMU at
the IMU rate and HEARTBEAT (channel names and the node: section from --config). Calibration: the config's, replaced by
--calib (a EuRoC folder's cam0/cam1 sensor.yaml) or --calib-from-sim (a scenario's camera).
Stops on SIGINT/SIGTERM after tracking the frames already queued, and prints a summary.
Demo (hs-sim output replayed at sensor rate):
  hs-tracker --calib /data/sim/room_mav &
  hs-record-trajectory --channel POSE --out pose.tum --idle-timeout 5 &
  lcm-logplayer room_mav.lcmlog
Exit status: 0 after a clean stop, 1 on bad configuration or LCM errors.)";

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  const auto s = [](const timeval& t) { return static_cast<double>(t.tv_sec) + t.tv_usec * 1e-6; };
  return s(u.ru_utime) + s(u.ru_stime);
}

void print_summary(const hs::NodeStats& s, double wall_s) {
  const double cpu_s = cpu_seconds();
  std::printf(
      "hs-tracker: %lld frames received, %lld tracked (%lld poses, %lld keyframes), %lld dropped "
      "(queue full), %lld bad frame / %lld bad IMU messages, %lld tracker errors, %lld POSE_IMU; "
      "tracking %.2f ms/frame; CPU %.2f s over %.2f s (%.0f%%)\n",
      static_cast<long long>(s.frames_received), static_cast<long long>(s.frames_tracked),
      static_cast<long long>(s.poses_published), static_cast<long long>(s.keyframes_published),
      static_cast<long long>(s.frames_dropped), static_cast<long long>(s.bad_frame_messages),
      static_cast<long long>(s.bad_imu_messages), static_cast<long long>(s.tracker_errors),
      static_cast<long long>(s.pose_imu_published),
      s.frames_tracked ? s.tracking_ms / static_cast<double>(s.frames_tracked) : 0.0, cpu_s, wall_s,
      wall_s > 0 ? 100.0 * cpu_s / wall_s : 0.0);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hs-tracker: the HS-SLAM stereo-inertial tracker as an LCM process"};
  app.footer(kFooter);
  std::string config, calib_dir, sim_scenario, url = hs::default_lcm_url();
  app.add_option("--config", config, "tracker config (config/euroc.yaml; default: built in)");
  hs::add_rig_calib_options(app, calib_dir, sim_scenario);
  app.add_option("--lcm-url", url, "LCM URL ($LCM_DEFAULT_URL or the project default)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  hs::install_stop_signals();

  try {
    hs::TrackerOptions options =
        config.empty() ? hs::TrackerOptions{} : hs::load_tracker_options(config);
    hs::override_rig_calib(calib_dir, sim_scenario, options.calib);

    const std::string warning = hs::receive_buffer_warning(url);
    if (!warning.empty()) std::fprintf(stderr, "hs-tracker: warning: %s\n", warning.c_str());
    auto lcm = hs::connect_lcm(url);
    const auto start = std::chrono::steady_clock::now();
    hs::TrackerNode node(*lcm, options);
    node.start();
    std::printf("hs-tracker: listening on %s (%s, %s), frame queue %d\n", url.c_str(),
                options.channels.cam_stereo.c_str(), options.channels.imu.c_str(),
                options.node.frame_queue_size);
    std::fflush(stdout);  // tells a supervising script that the subscriptions are live

    hs::handle_until_stopped(*lcm, [&] { node.poll(); });
    node.stop();
    print_summary(node.stats(),
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hs-tracker: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
