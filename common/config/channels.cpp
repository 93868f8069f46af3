#include "common/config/channels.h"

#include <array>
#include <map>
#include <utility>

namespace hs {
namespace {

using Field = std::pair<const char*, std::string ChannelNames::*>;
constexpr std::array<Field, 13> kFields = {{
    {"CAM_STEREO", &ChannelNames::cam_stereo},
    {"IMU", &ChannelNames::imu},
    {"TRIGGER", &ChannelNames::trigger},
    {"POSE", &ChannelNames::pose},
    {"POSE_IMU", &ChannelNames::pose_imu},
    {"TRACKER_STATUS", &ChannelNames::tracker_status},
    {"KEYFRAME", &ChannelNames::keyframe},
    {"MAP_UPDATE", &ChannelNames::map_update},
    {"MAP_COMMAND", &ChannelNames::map_command},
    {"RELOC_REQUEST", &ChannelNames::reloc_request},
    {"RELOC_ANSWER", &ChannelNames::reloc_answer},
    {"HEARTBEAT", &ChannelNames::heartbeat},
    {"GROUND_TRUTH", &ChannelNames::ground_truth},
}};

}  // namespace

ChannelNames read_channel_names(ConfigSection& top) {
  ChannelNames names;
  top.section("channels", [&](ConfigSection& s) {
    std::map<std::string, std::string> used;  // channel -> logical name
    for (const auto& [key, member] : kFields) {
      std::string& value = names.*member;
      if (!s.read(key, value)) continue;
      if (value.empty() || value.find_first_of(" \t\r\n") != std::string::npos)
        s.fail(key, "a channel name must be non-empty and contain no whitespace");
    }
    for (const auto& [key, member] : kFields) {
      const auto [it, fresh] = used.emplace(names.*member, key);
      if (!fresh) s.fail(key, "channel '" + names.*member + "' is also used for " + it->second);
    }
  });
  return names;
}

ChannelNames load_channel_names(const std::string& path) {
  ConfigSection top = ConfigSection::load(path);
  const ChannelNames names = read_channel_names(top);
  top.finish();
  return names;
}

}  // namespace hs
