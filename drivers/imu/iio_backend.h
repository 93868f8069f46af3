#pragma once
// Linux IIO in buffered mode (IioDevice), with checks on the kernel's timestamps: a sample not
// after the previous one is dropped, so is one far from CLOCK_MONOTONIC's now (a driver whose
// timestamps are on another clock), and at a known rate gaps count the samples missing.
#include <memory>

#include "drivers/imu/iio_device.h"
#include "drivers/imu/imu_backend.h"
#include "drivers/imu/imu_pairing.h"

namespace hs {

struct IioCheckCounters {
  int64_t backwards = 0;     // not after the previous sample: dropped
  int64_t off_clock = 0;     // further than the buffer's span from now: dropped
  int64_t lost_samples = 0;  // from gaps over 1.5 periods (when the rate is configured)
};

// The checks alone, on samples and the host time they were read at.
class IioTimestampCheck {
 public:
  // `max_age_ns`: the oldest a buffered sample can be; `rate_hz` 0: no gap counting.
  IioTimestampCheck(int64_t max_age_ns, double rate_hz);
  // Keeps the good samples of `samples` (read at host time `now_ns`).
  void filter(std::vector<ImuSample>* samples, int64_t now_ns);
  void restart() { last_t_ns_ = -1; }  // a reopened device
  const IioCheckCounters& counters() const { return counters_; }
  const std::string& last_error() const { return last_error_; }

 private:
  int64_t max_age_ns_;
  double rate_hz_;
  int64_t last_t_ns_ = -1;
  IioCheckCounters counters_;
  std::string last_error_;
};

// One IIO device, or an accelerometer and a gyroscope device paired (options.gyro_device).
class IioBackend : public ImuBackend {
 public:
  explicit IioBackend(const IioOptions& options);
  void open() override;
  void close() override;
  ReadStatus read(int timeout_ms, std::vector<ImuSample>* samples) override;
  std::string device() const override;
  int64_t bad_input() const override;
  const std::string& last_error() const override { return last_error_; }
  Counters counters() const override;

 private:
  // Accelerometer and gyroscope as two IIO devices (a BMI088's two drivers).
  bool split() const { return !options_.gyro_device.empty(); }
  IioDevice::ReadStatus read_checked(IioDevice& device, IioTimestampCheck& check, int timeout_ms,
                                     std::vector<ImuSample>* samples);

  IioOptions options_;
  std::unique_ptr<IioDevice> device_, gyro_device_;
  IioTimestampCheck check_, gyro_check_;
  ImuPairer pairer_;
  int64_t scans_ = 0;
  std::string last_error_;
};

}  // namespace hs
