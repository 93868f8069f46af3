#pragma once
// The LCM log file format (what lcm-logger writes and lcm-logplayer reads), one event after
// another, all integers big-endian:
//   uint32 sync word 0xEDA1DA01, int64 event number, int64 timestamp (us), int32 channel length,
//   int32 data length, channel bytes, data bytes.
// The writer side only encodes; the reader scans a file and survives what power cuts leave: a
// torn last event is detected and skipped, and garbage inside the file is skipped up to the next
// valid event header.
#include <cstdint>
#include <string>
#include <vector>

namespace hs {

constexpr uint32_t kLcmLogSyncWord = 0xEDA1DA01u;
constexpr size_t kLcmLogHeaderSize = 4 + 8 + 8 + 4 + 4;
// lcm-logplayer rejects longer channel names.
constexpr size_t kLcmMaxChannelLength = 255;

struct LogEvent {
  int64_t event_number = 0;
  int64_t utime = 0;  // microseconds (receive time for a recorded log)
  std::string channel;
  std::vector<uint8_t> data;
};

// Appends the encoded event to `out`.
void append_log_event(int64_t event_number, int64_t utime, const std::string& channel,
                      const uint8_t* data, size_t size, std::vector<uint8_t>* out);
inline void append_log_event(const LogEvent& e, std::vector<uint8_t>* out) {
  append_log_event(e.event_number, e.utime, e.channel, e.data.data(), e.data.size(), out);
}

struct LogScan {
  std::vector<LogEvent> events;
  int64_t torn_tail_bytes = 0;  // an incomplete last event (cut by a crash), skipped
  int64_t skipped_bytes = 0;    // not the start of a valid event, skipped to the next one
  int64_t skipped_regions = 0;
};

// Reads every complete event of the file. Throws InputError when the file cannot be read.
LogScan scan_log_file(const std::string& path);

}  // namespace hs
