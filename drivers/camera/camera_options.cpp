#include "drivers/camera/camera_options.h"

#include "common/config/process_section.h"

namespace hs {

CameraOptions load_camera_options(const std::string& path) {
  CameraOptions o;
  ConfigSection top = ConfigSection::load(path);
  top.section("camera", [&](ConfigSection& s) {
    s.read("devices", o.devices);
    if (o.devices.empty() || o.devices.size() > 2) s.fail("devices", "one or two devices");
    s.read("side_by_side", o.side_by_side);
    if (o.side_by_side && o.devices.size() != 1) s.fail("side_by_side", "needs exactly one device");
    s.read("width", o.format.width);
    s.read("height", o.format.height);
    if (o.format.width <= 0 || o.format.height <= 0) s.fail("width", "must be > 0");
    std::string format = "GREY";
    s.read("format", format);
    try {
      o.format.format = pixel_format_from_name(format);
    } catch (const std::exception& e) {
      s.fail("format", e.what());
    }
    s.read("fps", o.format.fps);
    if (!(o.format.fps > 0 && o.format.fps <= 500)) s.fail("fps", "must be in (0, 500]");
    s.read_seconds("exposure_s", o.format.exposure_ns);
    s.read("exposure_control", o.format.exposure_control);
    s.read("gain", o.format.gain);
    std::string mode = "free-running";
    s.read("mode", mode);
    if (mode != "free-running" && mode != "external-trigger")
      s.fail("mode", "must be free-running or external-trigger");
    o.mode = mode == "free-running" ? TriggerMode::kFreeRunning : TriggerMode::kExternal;
    if (o.mode == TriggerMode::kExternal && o.format.exposure_ns <= 0)
      s.fail("exposure_s", "external-trigger mode needs the exposure (mid-exposure stamps)");
    s.read_seconds("readout_s", o.readout_ns);
    s.read_period("max_stereo_skew_s", o.max_stereo_skew_ns);
    std::string encoding = "mono8";
    s.read("encoding", encoding);
    try {
      o.encoding = parse_image_encoding(encoding);
    } catch (const std::exception& e) {
      s.fail("encoding", e.what());
    }
    s.read_period("reconnect_period_s", o.reconnect_period_ns);
  });
  top.section("trigger_pairing", [&](ConfigSection& s) {
    s.read_period("max_latency_s", o.trigger.max_latency_ns);
    s.read_period("max_wait_s", o.trigger.max_wait_ns);
  });
  read_process_tail(top, o.heartbeat_period_ns, o.channels);
  return o;
}

}  // namespace hs
