#include "drivers/imu/xsens_backend.h"

#include "common/core/monotonic_clock.h"

namespace hs {
namespace {

DeviceClockOptions xsens_clock(DeviceClockOptions clock, int baud) {
  clock.device_hz = kXsensSampleTimeHz;
  clock.counter_bits = 32;
  clock.transmission_ns = transmission_ns(kXsensMessageBytes, baud);
  return clock;
}

}  // namespace

XsensBackend::XsensBackend(const ImuDriverOptions& options)
    : device_(options.device),
      baud_(options.baud),
      stream_(xsens_clock(options.clock, options.baud)) {}

void XsensBackend::open() {
  port_ = std::make_unique<SerialPort>(device_, baud_);
  if (opens_++ > 0) stream_.reset();  // a new session of the device's counters
}

ImuBackend::ReadStatus XsensBackend::read(int timeout_ms, std::vector<ImuSample>* samples) {
  size_t got = 0;
  const SerialPort::ReadStatus status =
      port_->read(buffer_.data(), buffer_.size(), timeout_ms, &got);
  if (status == SerialPort::ReadStatus::kTimeout) return ReadStatus::kTimeout;
  if (status == SerialPort::ReadStatus::kLost) return ReadStatus::kLost;
  const std::vector<ImuSample> fed = stream_.feed(buffer_.data(), got, monotonic_ns());
  samples->insert(samples->end(), fed.begin(), fed.end());
  return ReadStatus::kData;
}

std::string XsensBackend::device() const {
  return device_ + " at " + std::to_string(baud_) + " baud";
}

int64_t XsensBackend::bad_input() const {
  const XsensCounters p = stream_.protocol();
  return p.bad_checksum + p.malformed + p.incomplete + stream_.counters().backwards;
}

ImuBackend::Counters XsensBackend::counters() const {
  const XsensCounters p = stream_.protocol();
  const XsensStreamCounters& c = stream_.counters();
  return {{"bad_checksum", p.bad_checksum},
          {"malformed", p.malformed},
          {"incomplete", p.incomplete},
          {"other_messages", p.other_messages},
          {"skipped_bytes", p.skipped_bytes},
          {"lost_samples", c.lost_samples},
          {"backwards_timestamps", c.backwards},
          {"clock_offset_us", stream_.clock().offset_ns() / 1000}};
}

}  // namespace hs
