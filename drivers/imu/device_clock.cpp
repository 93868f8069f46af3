#include "drivers/imu/device_clock.h"

#include <cmath>

namespace hs {

DeviceClock::DeviceClock(const DeviceClockOptions& options) : options_(options) {}

int64_t DeviceClock::to_host(uint64_t counter, int64_t receive_ns) {
  const uint64_t modulus = options_.counter_bits >= 64 ? 0 : (uint64_t{1} << options_.counter_bits);
  if (started_ && modulus != 0 && counter < last_counter_ && last_counter_ - counter > modulus / 2)
    ++wraps_;  // a large step back is the counter wrapping, not time going back
  started_ = true;
  last_counter_ = counter;
  const long double ticks =
      static_cast<long double>(counter) + static_cast<long double>(wraps_) * modulus;
  const int64_t device_ns = static_cast<int64_t>(std::llround(ticks * 1e9L / options_.device_hz));
  // Sliding-window minimum of receive - device (monotonic deque).
  const int64_t sample_offset = receive_ns - device_ns;
  while (!candidates_.empty() && candidates_.back().second >= sample_offset) candidates_.pop_back();
  candidates_.emplace_back(receive_ns, sample_offset);
  while (candidates_.front().first < receive_ns - options_.window_ns) candidates_.pop_front();
  offset_ns_ = candidates_.front().second - options_.transmission_ns;
  int64_t host = device_ns + offset_ns_;
  // The offset may rise as the window slides (drift): never let that step time back.
  if (host <= last_host_ns_) host = last_host_ns_ + 1;
  last_host_ns_ = host;
  return host;
}

}  // namespace hs
