#pragma once
// All options of hs-logger, from one YAML config (config/logger.yaml documents every key).
#include <cstdint>
#include <string>
#include <vector>

#include "common/config/channels.h"
#include "logger/log_writer.h"

namespace hs {

struct LoggerOptions {
  LogWriterOptions writer;
  std::vector<std::string> include = {".*"};  // channel regexes (whole-name match)
  std::vector<std::string> exclude;
  bool png_images = false;  // CAM_STEREO MONO8 images recorded as PNG (lossless)
  int64_t heartbeat_period_ns = 1'000'000'000;
  ChannelNames channels;
};

// Unknown keys, wrong types or bad values: InputError with file:line.
LoggerOptions load_logger_options(const std::string& path);

}  // namespace hs
