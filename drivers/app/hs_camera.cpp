// hs-camera: the camera driver. Captures one or two V4L2 devices and publishes CAM_STEREO stamped
// at mid-exposure on CLOCK_MONOTONIC, free-running or paired with hs-trigger's pulses.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "common/core/stop_signal.h"
#include "common/lcm/lcm_connection.h"
#include "drivers/camera/camera_node.h"
#include "drivers/camera/camera_options.h"

int main(int argc, char** argv) {
  CLI::App app{"hs-camera: V4L2 stereo capture publishing CAM_STEREO at mid-exposure"};
  app.footer(R"(
Free-running: the V4L2 buffer timestamp (which must be CLOCK_MONOTONIC) converted to
mid-exposure (start-of-exposure stamps + half the exposure; end-of-frame stamps - readout - half
the exposure). External trigger: the time of the frame's TRIGGER pulse + half the exposure, the
pulse matched by sequence with a check that the buffer followed it. Dropped frames are counted
from sequence gaps; left and right are paired by time; frames without a partner or a pulse are
counted and not published. A missing or lost device is reopened every reconnect period. Stops on
SIGINT/SIGTERM.)");
  std::string config, url = hs::default_lcm_url();
  app.add_option("--config", config, "camera config (config/camera.yaml; default: built in)");
  app.add_option("--lcm-url", url, "LCM URL ($LCM_DEFAULT_URL or the project default)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  hs::install_stop_signals();
  try {
    hs::CameraOptions options;
    if (!config.empty()) options = hs::load_camera_options(config);
    auto lcm = hs::connect_lcm(url);
    hs::CameraNode node(*lcm, options);
    std::printf("hs-camera: %zu device(s), %dx%d at %.1f fps, publishing %s on %s\n",
                options.devices.size(), options.format.width, options.format.height,
                options.format.fps, options.channels.cam_stereo.c_str(), url.c_str());
    std::fflush(stdout);
    node.run();
    const hs::CameraStats& s = node.stats();
    const hs::StereoPairStats& p = node.pairing();
    const hs::TriggerMatchStats t = node.trigger_matching();
    std::printf(
        "hs-camera: %lld + %lld frames, %lld published; dropped by the devices %lld + %lld; "
        "unpaired %lld + %lld; matched to their trigger %lld, without trigger %lld, triggers "
        "without frame %lld, trigger time mismatches %lld, relocks %lld; bad %lld; %lld device "
        "losses\n",
        static_cast<long long>(s.frames[0]), static_cast<long long>(s.frames[1]),
        static_cast<long long>(s.published), static_cast<long long>(node.dropped(0)),
        static_cast<long long>(options.devices.size() > 1 ? node.dropped(1) : 0),
        static_cast<long long>(p.unpaired_left), static_cast<long long>(p.unpaired_right),
        static_cast<long long>(t.matched), static_cast<long long>(t.frames_without_trigger),
        static_cast<long long>(t.triggers_without_frame), static_cast<long long>(t.time_mismatches),
        static_cast<long long>(t.relocks), static_cast<long long>(s.bad_frames),
        static_cast<long long>(s.device_lost));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hs-camera: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
