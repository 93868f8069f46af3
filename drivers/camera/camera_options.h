#pragma once
// All options of hs-camera, from one YAML config (config/camera.yaml documents every key).
#include <cstdint>
#include <string>
#include <vector>

#include "common/config/channels.h"
#include "common/lcm/convert.h"
#include "drivers/camera/trigger_matcher.h"
#include "drivers/camera/v4l2_device.h"

namespace hs {

enum class TriggerMode { kFreeRunning, kExternal };

struct CameraOptions {
  // One device (mono, or both images side by side) or two (left, right).
  std::vector<std::string> devices = {"/dev/video0", "/dev/video1"};
  bool side_by_side = false;
  V4l2Format format;  // per device (side by side: the whole double image)
  TriggerMode mode = TriggerMode::kFreeRunning;
  int64_t readout_ns = 0;                  // end-of-frame stamped devices: the frame's readout time
  int64_t max_stereo_skew_ns = 2'000'000;  // left and right of one pair at most this apart
  TriggerMatcherOptions trigger;
  ImageEncoding encoding = ImageEncoding::kMono8;
  int64_t reconnect_period_ns = 1'000'000'000;
  int64_t heartbeat_period_ns = 1'000'000'000;
  ChannelNames channels;
};

// Unknown keys, wrong types or bad values: InputError with file:line.
CameraOptions load_camera_options(const std::string& path);

}  // namespace hs
