#pragma once
// LCM channel names. Defaults equal the logical names; a config file may rename them in a
// `channels:` section (see config/channels.yaml).
#include <string>

#include "common/config/config_section.h"

namespace hs {

struct ChannelNames {
  std::string cam_stereo = "CAM_STEREO";
  std::string imu = "IMU";
  std::string trigger = "TRIGGER";
  std::string pose = "POSE";
  std::string pose_imu = "POSE_IMU";
  std::string tracker_status = "TRACKER_STATUS";
  std::string keyframe = "KEYFRAME";
  std::string map_update = "MAP_UPDATE";
  std::string map_command = "MAP_COMMAND";
  std::string reloc_request = "RELOC_REQUEST";
  std::string reloc_answer = "RELOC_ANSWER";
  std::string heartbeat = "HEARTBEAT";
  std::string ground_truth = "GROUND_TRUTH";
};

// Reads the optional `channels:` section of a process config (keys are the logical names,
// e.g. `CAM_STEREO: CAM_STEREO_LEFT_RIG`). Names must be non-empty, without whitespace, and
// distinct.
ChannelNames read_channel_names(ConfigSection& top);

// A file whose only top-level key is `channels:` (as config/channels.yaml).
ChannelNames load_channel_names(const std::string& path);

}  // namespace hs
