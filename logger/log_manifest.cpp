#include "logger/log_manifest.h"

#include "hsslam/imu_batch_t.hpp"
#include "hsslam/map_update_t.hpp"
#include "hsslam/odometry_t.hpp"
#include "hsslam/stereo_frame_t.hpp"
#include "hsslam/tracker_status_t.hpp"
#include "hsslam/trigger_t.hpp"

namespace hs {

namespace {

constexpr size_t kMaxListedGaps = 100;

uint64_t be64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];
  return v;
}

}  // namespace

int64_t message_seq(const uint8_t* data, size_t size) {
  // Fingerprint (8 bytes), t_ns (8), seq (8).
  if (size < 24) return -1;
  const int64_t hash = static_cast<int64_t>(be64(data));
  for (const int64_t h : {hsslam::stereo_frame_t::getHash(), hsslam::imu_batch_t::getHash(),
                          hsslam::odometry_t::getHash(), hsslam::tracker_status_t::getHash(),
                          hsslam::map_update_t::getHash(), hsslam::trigger_t::getHash()}) {
    if (hash == h) return static_cast<int64_t>(be64(data + 16));
  }
  return -1;
}

void LogManifest::add(const std::string& channel, int64_t utime, int64_t bytes, int64_t seq) {
  ChannelStats& c = channels_[channel];
  if (c.messages == 0) c.first_utime = utime;
  c.last_utime = utime;
  ++c.messages;
  c.bytes += bytes;
  if (seq < 0) return;
  c.sequenced = true;
  if (c.last_seq >= 0 && seq <= c.last_seq) {
    ++c.seq_restarts;
  } else if (c.last_seq >= 0 && seq > c.last_seq + 1) {
    c.lost += seq - c.last_seq - 1;
    if (c.gaps.size() < kMaxListedGaps) c.gaps.emplace_back(c.last_seq, seq);
  }
  c.last_seq = seq;
}

int64_t LogManifest::messages() const {
  int64_t n = 0;
  for (const auto& [name, c] : channels_) n += c.messages;
  return n;
}

nlohmann::json LogManifest::to_json() const {
  nlohmann::json j = nlohmann::json::object();
  int64_t first = 0, last = 0;
  nlohmann::json channels = nlohmann::json::object();
  for (const auto& [name, c] : channels_) {
    nlohmann::json cj = {{"messages", c.messages},
                         {"bytes", c.bytes},
                         {"first_utime", c.first_utime},
                         {"last_utime", c.last_utime}};
    if (c.sequenced) {
      cj["lost_upstream"] = c.lost;
      cj["seq_restarts"] = c.seq_restarts;
      cj["gaps"] = c.gaps;
    }
    channels[name] = cj;
    first = first == 0 ? c.first_utime : std::min(first, c.first_utime);
    last = std::max(last, c.last_utime);
  }
  j["messages"] = messages();
  j["first_utime"] = first;
  j["last_utime"] = last;
  j["duration_s"] = 1e-6 * static_cast<double>(last - first);
  j["channels"] = channels;
  return j;
}

}  // namespace hs
