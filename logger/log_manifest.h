#pragma once
// What one log file holds, written beside it as FILE.manifest.json when the file is closed:
// per channel the message count, bytes and time span, and the messages lost upstream, found as
// gaps in the `seq` field of the project's sequenced types (stereo_frame_t, imu_batch_t,
// odometry_t, tracker_status_t, map_update_t, trigger_t: seq follows t_ns in each).
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace hs {

struct ChannelStats {
  int64_t messages = 0;
  int64_t bytes = 0;
  int64_t first_utime = 0, last_utime = 0;
  // Sequenced channels only: missing seq values (a restart from 0 is not a gap), and how often
  // seq went back (a restarted publisher).
  bool sequenced = false;
  int64_t last_seq = -1;
  int64_t lost = 0;
  int64_t seq_restarts = 0;
  std::vector<std::pair<int64_t, int64_t>> gaps;  // (last seq before, first seq after), first 100
};

class LogManifest {
 public:
  // `seq`: message_seq() of the message (-1: not a sequenced type).
  void add(const std::string& channel, int64_t utime, int64_t bytes, int64_t seq);
  const std::map<std::string, ChannelStats>& channels() const { return channels_; }
  int64_t messages() const;
  nlohmann::json to_json() const;

 private:
  std::map<std::string, ChannelStats> channels_;
};

// seq of a message of one of the sequenced types, by its fingerprint; -1 for other types.
int64_t message_seq(const uint8_t* data, size_t size);

}  // namespace hs
