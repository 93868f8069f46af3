#pragma once
// IMUs whose accelerometer and gyroscope are separate devices with their own clocks of samples
// (BMI088, ICM-42688 with two IIO drivers...): one stream of ImuSample at the gyroscope's times,
// the acceleration interpolated linearly between the accelerometer samples around each. The
// gyroscope sets the times because rotation is what propagation integrates most finely.
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "common/core/types.h"

namespace hs {

struct ImuPairingCounters {
  int64_t paired = 0;
  int64_t unpaired_gyro = 0;  // no accelerometer samples around it within the gap: dropped
  int64_t leading_gyro = 0;   // before the accelerometer's first sample (after a (re)start)
};

class ImuPairer {
 public:
  // `max_gap_ns`: the longest accelerometer interval interpolated across; `max_wait_ns`: how far
  // gyroscope samples may run ahead of the accelerometer before the oldest are dropped.
  ImuPairer(int64_t max_gap_ns, int64_t max_wait_ns);

  // Samples of each device in time order (only their accel or gyro is used).
  void add_accel(const std::vector<ImuSample>& samples);
  void add_gyro(const std::vector<ImuSample>& samples);
  // The gyroscope samples now bracketed by accelerometer samples, appended in time order.
  void take(std::vector<ImuSample>* out);
  void restart();  // reopened devices: nothing carries over

  const ImuPairingCounters& counters() const { return counters_; }
  const std::string& last_error() const { return last_error_; }

 private:
  void drop(const ImuSample& gyro, const std::string& why);

  int64_t max_gap_ns_, max_wait_ns_;
  std::deque<ImuSample> accel_, gyro_;
  ImuPairingCounters counters_;
  std::string last_error_;
};

}  // namespace hs
