#include "drivers/imu/iio_backend.h"

#include <cmath>

#include "common/core/monotonic_clock.h"

namespace hs {
namespace {

// The oldest sample a full kernel buffer can hold, with a margin; 10 s when the rate is unknown.
int64_t buffer_span_ns(const IioOptions& o) {
  if (o.sampling_frequency_hz <= 0) return 10'000'000'000;
  return static_cast<int64_t>(2e9 * o.buffer_length / o.sampling_frequency_hz) + 1'000'000'000;
}

}  // namespace

IioTimestampCheck::IioTimestampCheck(int64_t max_age_ns, double rate_hz)
    : max_age_ns_(max_age_ns), rate_hz_(rate_hz) {}

void IioTimestampCheck::filter(std::vector<ImuSample>* samples, int64_t now_ns) {
  size_t kept = 0;
  for (const ImuSample& s : *samples) {
    if (s.t_ns > now_ns || now_ns - s.t_ns > max_age_ns_) {
      ++counters_.off_clock;
      last_error_ = "IIO timestamp " + std::to_string(s.t_ns) + " ns is " +
                    std::to_string((now_ns - s.t_ns) / 1'000'000) +
                    " ms before CLOCK_MONOTONIC's now: not on the camera's clock, dropped";
      continue;
    }
    if (last_t_ns_ >= 0 && s.t_ns <= last_t_ns_) {
      ++counters_.backwards;
      last_error_ = "IIO timestamp went back or repeated (" + std::to_string(last_t_ns_) + " -> " +
                    std::to_string(s.t_ns) + " ns): sample dropped";
      continue;
    }
    if (last_t_ns_ >= 0 && rate_hz_ > 0) {
      const double periods = static_cast<double>(s.t_ns - last_t_ns_) * 1e-9 * rate_hz_;
      if (periods > 1.5) counters_.lost_samples += std::llround(periods) - 1;
    }
    last_t_ns_ = s.t_ns;
    (*samples)[kept++] = s;
  }
  samples->resize(kept);
}

IioBackend::IioBackend(const IioOptions& options)
    : options_(options), check_(buffer_span_ns(options), options.sampling_frequency_hz) {}

void IioBackend::open() {
  device_ = std::make_unique<IioDevice>(options_);
  check_.restart();
}

ImuBackend::ReadStatus IioBackend::read(int timeout_ms, std::vector<ImuSample>* samples) {
  std::vector<ImuSample> read;
  const IioDevice::ReadStatus status = device_->read(timeout_ms, &read);
  if (status == IioDevice::ReadStatus::kTimeout) return ReadStatus::kTimeout;
  if (status == IioDevice::ReadStatus::kLost) return ReadStatus::kLost;
  scans_ += static_cast<int64_t>(read.size());
  check_.filter(&read, monotonic_ns());
  samples->insert(samples->end(), read.begin(), read.end());
  return ReadStatus::kData;
}

std::string IioBackend::device() const {
  return device_ ? device_->name() : "IIO device " + options_.device;
}

int64_t IioBackend::bad_input() const {
  return check_.counters().backwards + check_.counters().off_clock;
}

ImuBackend::Counters IioBackend::counters() const {
  const IioCheckCounters& c = check_.counters();
  return {{"scans_read", scans_},
          {"backwards_timestamps", c.backwards},
          {"off_clock_timestamps", c.off_clock},
          {"lost_samples", c.lost_samples}};
}

}  // namespace hs
