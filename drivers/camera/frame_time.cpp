#include "drivers/camera/frame_time.h"

#include <linux/videodev2.h>

#include <stdexcept>

namespace hs {

std::string describe_timestamp_flags(uint32_t flags) {
  std::string clock;
  switch (flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) {
    case V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC:
      clock = "monotonic";
      break;
    case V4L2_BUF_FLAG_TIMESTAMP_COPY:
      clock = "copied from output";
      break;
    default:
      clock = "unknown clock";
  }
  const bool soe = (flags & V4L2_BUF_FLAG_TSTAMP_SRC_MASK) == V4L2_BUF_FLAG_TSTAMP_SRC_SOE;
  return clock + (soe ? ", start of exposure" : ", end of frame");
}

int64_t mid_exposure_ns(const BufferTime& buffer, int64_t exposure_ns, int64_t readout_ns) {
  if ((buffer.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) != V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC)
    throw std::runtime_error("buffer timestamps are not CLOCK_MONOTONIC (" +
                             describe_timestamp_flags(buffer.flags) +
                             "): use external-trigger mode");
  if ((buffer.flags & V4L2_BUF_FLAG_TSTAMP_SRC_MASK) == V4L2_BUF_FLAG_TSTAMP_SRC_SOE)
    return buffer.t_ns + exposure_ns / 2;
  return buffer.t_ns - readout_ns - exposure_ns / 2;
}

}  // namespace hs
