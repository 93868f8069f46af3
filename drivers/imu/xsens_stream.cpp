#include "drivers/imu/xsens_stream.h"

namespace hs {

XsensStream::XsensStream(const DeviceClockOptions& clock) : clock_options_(clock), clock_(clock) {}

std::vector<ImuSample> XsensStream::feed(const uint8_t* data, size_t size, int64_t receive_ns) {
  std::vector<XsensSample> raw;
  parser_.feed(data, size, &raw);
  std::vector<ImuSample> out;
  for (const XsensSample& s : raw) {
    if (last_) {
      const uint32_t step = s.sample_time_fine - last_->sample_time_fine;  // modulo 2^32
      if (step == 0 || step > (1u << 31)) {
        ++counters_.backwards;
        last_error_ = "device time went back or repeated (SampleTimeFine " +
                      std::to_string(last_->sample_time_fine) + " -> " +
                      std::to_string(s.sample_time_fine) + "): sample dropped";
        continue;
      }
      const uint16_t expected = static_cast<uint16_t>(last_->packet_counter + 1);
      counters_.lost_samples += static_cast<uint16_t>(s.packet_counter - expected);
    }
    last_ = s;
    ImuSample sample;
    sample.t_ns = clock_.to_host(s.sample_time_fine, receive_ns);
    sample.accel = s.accel;
    sample.gyro = s.gyro;
    out.push_back(sample);
  }
  if (!parser_.last_error().empty()) last_error_ = parser_.last_error();
  return out;
}

XsensCounters XsensStream::protocol() const {
  XsensCounters sum = before_reset_;
  sum += parser_.counters();
  return sum;
}

void XsensStream::reset() {
  before_reset_ = protocol();
  parser_ = XsensParser();
  clock_ = DeviceClock(clock_options_);
  last_.reset();
  ++counters_.clock_restarts;
}

}  // namespace hs
