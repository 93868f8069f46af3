#pragma once
// Xsens bytes as they arrive -> IMU samples on the host's CLOCK_MONOTONIC: the protocol parser,
// the device clock mapping (SampleTimeFine), and the checks on what the device says: a sample
// whose device time does not advance is dropped and counted, and gaps in the packet counter are
// counted as samples lost on the way (serial overrun, a busy host).
#include <cstdint>
#include <optional>
#include <vector>

#include "common/core/types.h"
#include "drivers/imu/device_clock.h"
#include "drivers/imu/xsens_protocol.h"

namespace hs {

struct XsensStreamCounters {
  int64_t lost_samples = 0;    // packet-counter gaps
  int64_t backwards = 0;       // device time not after the previous sample's: dropped
  int64_t clock_restarts = 0;  // reset() calls (a reconnected device)
};

class XsensStream {
 public:
  explicit XsensStream(const DeviceClockOptions& clock);

  // Bytes read at host time `receive_ns` (CLOCK_MONOTONIC, taken right after the read).
  std::vector<ImuSample> feed(const uint8_t* data, size_t size, int64_t receive_ns);
  // A reconnected device: its counters start anew, so do the clock mapping and the parser.
  void reset();

  // Cumulative over reconnects.
  XsensCounters protocol() const;
  const XsensStreamCounters& counters() const { return counters_; }
  const DeviceClock& clock() const { return clock_; }
  const std::string& last_error() const { return last_error_; }

 private:
  DeviceClockOptions clock_options_;
  XsensParser parser_;
  XsensCounters before_reset_;  // the protocol counters of the parsers before the current one
  DeviceClock clock_;
  XsensStreamCounters counters_;
  std::optional<XsensSample> last_;
  std::string last_error_;
};

}  // namespace hs
