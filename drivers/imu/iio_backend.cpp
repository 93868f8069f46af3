#include "drivers/imu/iio_backend.h"

#include <poll.h>

#include <cerrno>
#include <cmath>

#include "common/core/monotonic_clock.h"

namespace hs {
namespace {

// The oldest sample a full kernel buffer can hold, with a margin; 10 s when the rate is unknown.
int64_t buffer_span_ns(int buffer_length, double rate_hz) {
  if (rate_hz <= 0) return 10'000'000'000;
  return static_cast<int64_t>(2e9 * buffer_length / rate_hz) + 1'000'000'000;
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
    : options_(options),
      check_(buffer_span_ns(options.buffer_length, options.sampling_frequency_hz),
             options.sampling_frequency_hz),
      gyro_check_(buffer_span_ns(options.buffer_length, options.gyro_sampling_frequency_hz),
                  options.gyro_sampling_frequency_hz),
      // Gyroscope samples wait for the accelerometer sample after them at most a buffer's span.
      pairer_(static_cast<int64_t>(options.pair_max_gap_s * 1e9),
              buffer_span_ns(options.buffer_length, options.gyro_sampling_frequency_hz) / 2) {}

void IioBackend::open() {
  device_ = std::make_unique<IioDevice>(options_, split() ? IioPart::kAccel : IioPart::kBoth);
  if (split()) gyro_device_ = std::make_unique<IioDevice>(options_, IioPart::kGyro);
  check_.restart();
  gyro_check_.restart();
  pairer_.restart();
}

void IioBackend::close() {
  gyro_device_.reset();
  device_.reset();
}

IioDevice::ReadStatus IioBackend::read_checked(IioDevice& device, IioTimestampCheck& check,
                                               int timeout_ms, std::vector<ImuSample>* samples) {
  const IioDevice::ReadStatus status = device.read(timeout_ms, samples);
  scans_ += static_cast<int64_t>(samples->size());
  const IioCheckCounters before = check.counters();
  check.filter(samples, monotonic_ns());
  if (check.counters().backwards != before.backwards ||
      check.counters().off_clock != before.off_clock)
    last_error_ = device.name() + ": " + check.last_error();
  return status;
}

ImuBackend::ReadStatus IioBackend::read(int timeout_ms, std::vector<ImuSample>* samples) {
  using Status = IioDevice::ReadStatus;
  if (!split()) {
    std::vector<ImuSample> read;
    const Status status = read_checked(*device_, check_, timeout_ms, &read);
    samples->insert(samples->end(), read.begin(), read.end());
    return status == Status::kData   ? ReadStatus::kData
           : status == Status::kLost ? ReadStatus::kLost
                                     : ReadStatus::kTimeout;
  }
  pollfd fds[2] = {{device_->fd(), POLLIN, 0}, {gyro_device_->fd(), POLLIN, 0}};
  if (::poll(fds, 2, timeout_ms) < 0 && errno != EINTR) return ReadStatus::kLost;
  std::vector<ImuSample> accel, gyro;
  const Status a = read_checked(*device_, check_, 0, &accel);
  const Status g = read_checked(*gyro_device_, gyro_check_, 0, &gyro);
  if (a == Status::kLost || g == Status::kLost) return ReadStatus::kLost;
  const int64_t unpaired = pairer_.counters().unpaired_gyro;
  pairer_.add_accel(accel);
  pairer_.add_gyro(gyro);
  pairer_.take(samples);
  if (pairer_.counters().unpaired_gyro != unpaired) last_error_ = pairer_.last_error();
  // Data even when nothing paired yet: a timeout would flush a part-filled batch.
  return a == Status::kData || g == Status::kData ? ReadStatus::kData : ReadStatus::kTimeout;
}

std::string IioBackend::device() const {
  // The kernel's name once open, else the configured one.
  auto name = [](const std::unique_ptr<IioDevice>& d, const std::string& configured) {
    return d ? d->name() : "IIO device " + configured;
  };
  const std::string accel = name(device_, options_.device);
  return split() ? accel + " + " + name(gyro_device_, options_.gyro_device) : accel;
}

int64_t IioBackend::bad_input() const {
  return check_.counters().backwards + check_.counters().off_clock +
         gyro_check_.counters().backwards + gyro_check_.counters().off_clock +
         pairer_.counters().unpaired_gyro;
}

ImuBackend::Counters IioBackend::counters() const {
  const IioCheckCounters& c = check_.counters();
  const IioCheckCounters& g = gyro_check_.counters();
  Counters out = {{"scans_read", scans_},
                  {"backwards_timestamps", c.backwards + g.backwards},
                  {"off_clock_timestamps", c.off_clock + g.off_clock},
                  {"lost_samples", c.lost_samples + g.lost_samples}};
  if (split()) {
    out.emplace_back("paired_samples", pairer_.counters().paired);
    out.emplace_back("unpaired_gyro_samples", pairer_.counters().unpaired_gyro);
    out.emplace_back("leading_gyro_samples", pairer_.counters().leading_gyro);
  }
  return out;
}

}  // namespace hs
