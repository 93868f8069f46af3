#pragma once
// Maps a sensor's own sample clock onto the host's CLOCK_MONOTONIC, the clock every HS-SLAM
// timestamp is on. A sample's host receive time is its device time plus a fixed offset plus a
// variable delay (serial transmission, USB polling, scheduling) that is never negative, so the
// offset is the minimum of (receive - device) over a sliding window (the least-delayed samples),
// less the transmission time of one message that even the fastest sample spends on the wire.
// The window follows the slow drift between the two crystals. Device counters that wrap are
// unwrapped first.
#include <cstdint>
#include <deque>

namespace hs {

struct DeviceClockOptions {
  double device_hz = 10'000.0;         // counter rate
  int counter_bits = 32;               // it wraps at 2^bits
  int64_t window_ns = 10'000'000'000;  // minimum over this much history
  int64_t transmission_ns = 0;         // one message's time on the wire (bytes * 10 / baud)
};

class DeviceClock {
 public:
  explicit DeviceClock(const DeviceClockOptions& options);

  // Host time of a sample with device counter `counter`, received at host time `receive_ns`.
  // Strictly increasing as long as the counter is.
  int64_t to_host(uint64_t counter, int64_t receive_ns);
  // The current offset estimate (host - device), ns; 0 before the first sample.
  int64_t offset_ns() const { return offset_ns_; }
  int64_t wraps() const { return wraps_; }

 private:
  DeviceClockOptions options_;
  bool started_ = false;
  uint64_t last_counter_ = 0;
  int64_t wraps_ = 0;
  int64_t offset_ns_ = 0;
  int64_t last_host_ns_ = 0;
  // (receive time, receive - device) with increasing offsets: the front is the window's minimum.
  std::deque<std::pair<int64_t, int64_t>> candidates_;
};

}  // namespace hs
