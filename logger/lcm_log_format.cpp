#include "logger/lcm_log_format.h"

#include <fstream>
#include <iterator>

#include "common/core/error.h"

namespace hs {

namespace {

void put_be(uint64_t v, int bytes, std::vector<uint8_t>* out) {
  for (int i = bytes - 1; i >= 0; --i) out->push_back(static_cast<uint8_t>(v >> (8 * i)));
}

uint64_t get_be(const uint8_t* p, int bytes) {
  uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
  return v;
}

// The complete event starting at `pos`, or false when none starts there.
bool read_event(const std::vector<uint8_t>& bytes, size_t pos, LogEvent* e, size_t* size) {
  if (bytes.size() - pos < kLcmLogHeaderSize) return false;
  const uint8_t* p = &bytes[pos];
  if (get_be(p, 4) != kLcmLogSyncWord) return false;
  const uint64_t channel_len = get_be(p + 20, 4), data_len = get_be(p + 24, 4);
  if (channel_len == 0 || channel_len > kLcmMaxChannelLength || data_len >= (1u << 31))
    return false;
  *size = kLcmLogHeaderSize + channel_len + data_len;
  if (*size > bytes.size() - pos) return false;
  e->event_number = static_cast<int64_t>(get_be(p + 4, 8));
  e->utime = static_cast<int64_t>(get_be(p + 12, 8));
  e->channel.assign(reinterpret_cast<const char*>(p + kLcmLogHeaderSize), channel_len);
  e->data.assign(p + kLcmLogHeaderSize + channel_len, p + *size);
  return true;
}

}  // namespace

void append_log_event(int64_t event_number, int64_t utime, const std::string& channel,
                      const uint8_t* data, size_t size, std::vector<uint8_t>* out) {
  put_be(kLcmLogSyncWord, 4, out);
  put_be(static_cast<uint64_t>(event_number), 8, out);
  put_be(static_cast<uint64_t>(utime), 8, out);
  put_be(channel.size(), 4, out);
  put_be(size, 4, out);
  out->insert(out->end(), channel.begin(), channel.end());
  out->insert(out->end(), data, data + size);
}

LogScan scan_log_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw InputError(path + ": cannot open log file");
  std::vector<uint8_t> bytes(static_cast<size_t>(in.tellg()));
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size())))
    throw InputError(path + ": cannot read log file");
  LogScan scan;
  size_t pos = 0;
  while (pos < bytes.size()) {
    LogEvent e;
    size_t size = 0;
    if (read_event(bytes, pos, &e, &size)) {
      scan.events.push_back(std::move(e));
      pos += size;
      continue;
    }
    // No complete event here: skip to the next one. With none after it, this is the tail a
    // crash cut (an event half written, or a header cut short).
    size_t next = pos + 1;
    while (next < bytes.size() && !read_event(bytes, next, &e, &size)) ++next;
    if (next >= bytes.size()) {
      scan.torn_tail_bytes = static_cast<int64_t>(bytes.size() - pos);
      break;
    }
    scan.skipped_bytes += static_cast<int64_t>(next - pos);
    ++scan.skipped_regions;
    pos = next;
  }
  return scan;
}

}  // namespace hs
