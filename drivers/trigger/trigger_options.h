#pragma once
// All options of hs-trigger, from one YAML config (config/trigger.yaml documents every key).
#include <cstdint>
#include <string>

#include "common/config/channels.h"

namespace hs {

struct TriggerOptions {
  std::string chip = "gpiochip0";  // name (gpiochipN), path or label of the GPIO chip
  std::string output_line = "0";   // the cameras' trigger input: an offset or a line name
  std::string edge_line;  // loopback / strobe input giving the kernel's edge time ("": none)
  double rate_hz = 20.0;  // free-running; phase-locked, the data-ready rate / sync_divider
  // Phase lock to the IMU: pulse on every sync_divider-th rising edge of its data-ready line.
  std::string sync_line;                    // "": free-running at rate_hz
  int sync_divider = 10;                    // 200 Hz IMU -> 20 Hz cameras
  int64_t sync_timeout_ns = 1'000'000'000;  // no data-ready edge this long: said so
  int64_t pulse_width_ns = 1'000'000;
  int64_t edge_timeout_ns = 10'000'000;  // an edge later than this after the pulse is missing
  int64_t heartbeat_period_ns = 1'000'000'000;
  ChannelNames channels;
};

// Unknown keys, wrong types or bad values: InputError with file:line.
TriggerOptions load_trigger_options(const std::string& path);

}  // namespace hs
