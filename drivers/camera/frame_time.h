#pragma once
// The time of a V4L2 frame on CLOCK_MONOTONIC at mid-exposure, as EuRoC stamps images.
// Free-running cameras: the buffer timestamp must be on the monotonic clock
// (V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC); it marks the start of exposure (TSTAMP_SRC_SOE) or the end
// of the frame (TSTAMP_SRC_EOF: exposure, then readout, then the timestamp). Triggered cameras:
// the trigger edge starts the exposure.
#include <cstdint>
#include <string>

namespace hs {

struct BufferTime {
  int64_t t_ns = 0;    // the buffer's timestamp
  uint32_t flags = 0;  // v4l2_buffer.flags
};

// Mid-exposure from a free-running buffer; throws std::runtime_error when the timestamp is not
// CLOCK_MONOTONIC (a driver stamping another clock cannot be paired with the IMU).
int64_t mid_exposure_ns(const BufferTime& buffer, int64_t exposure_ns, int64_t readout_ns);

// Mid-exposure of a triggered frame.
inline int64_t mid_exposure_from_trigger_ns(int64_t trigger_ns, int64_t exposure_ns) {
  return trigger_ns + exposure_ns / 2;
}

// "monotonic, end of frame" etc., for messages.
std::string describe_timestamp_flags(uint32_t flags);

}  // namespace hs
