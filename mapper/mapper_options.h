#pragma once
// Loading MapperOptions (and the rig calibration the mapper needs) from one YAML config
// (config/mapper.yaml documents every key).
#include <string>

#include "common/calib/camera_calib.h"
#include "common/config/channels.h"
#include "mapper/mapper.h"

namespace hs {

struct MapperConfig {
  StereoCalib calib = euroc_stereo_calib();
  MapperOptions mapper;  // mapper.window.imu.noise from the calibration section
  ChannelNames channels;
  int64_t heartbeat_period_ns = 1'000'000'000;  // the hs-mapper process
};

// Unknown keys, wrong types or bad values: InputError with file:line.
MapperConfig load_mapper_config(const std::string& path);

}  // namespace hs
