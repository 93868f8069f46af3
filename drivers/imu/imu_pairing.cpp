#include "drivers/imu/imu_pairing.h"

namespace hs {

ImuPairer::ImuPairer(int64_t max_gap_ns, int64_t max_wait_ns)
    : max_gap_ns_(max_gap_ns), max_wait_ns_(max_wait_ns) {}

void ImuPairer::add_accel(const std::vector<ImuSample>& samples) {
  accel_.insert(accel_.end(), samples.begin(), samples.end());
}

void ImuPairer::add_gyro(const std::vector<ImuSample>& samples) {
  gyro_.insert(gyro_.end(), samples.begin(), samples.end());
}

void ImuPairer::drop(const ImuSample& gyro, const std::string& why) {
  ++counters_.unpaired_gyro;
  last_error_ = "gyroscope sample at " + std::to_string(gyro.t_ns) + " ns dropped: " + why;
}

void ImuPairer::take(std::vector<ImuSample>* out) {
  while (!gyro_.empty()) {
    const ImuSample& g = gyro_.front();
    // The accelerometer samples before the last one at or before g are no longer needed.
    while (accel_.size() >= 2 && accel_[1].t_ns <= g.t_ns) accel_.pop_front();
    if (!accel_.empty() && accel_.front().t_ns > g.t_ns) {
      ++counters_.leading_gyro;  // the devices started at different times: not an error
      gyro_.pop_front();
      continue;
    }
    if (accel_.empty()) {
      if (gyro_.back().t_ns - g.t_ns <= max_wait_ns_) return;  // its first sample is to come
      drop(g, "no accelerometer samples for " +
                  std::to_string((gyro_.back().t_ns - g.t_ns) / 1'000'000) + " ms");
      gyro_.pop_front();
      continue;
    }
    const ImuSample& a0 = accel_.front();
    if (a0.t_ns == g.t_ns) {
      out->push_back({g.t_ns, g.gyro, a0.accel});
    } else if (accel_.size() < 2) {
      if (g.t_ns - a0.t_ns <= max_gap_ns_ && gyro_.back().t_ns - g.t_ns <= max_wait_ns_)
        return;  // the accelerometer sample after g is still to come
      drop(g, "no accelerometer sample within " + std::to_string(max_gap_ns_ / 1'000'000) +
                  " ms after it");
      gyro_.pop_front();
      continue;
    } else {
      const ImuSample& a1 = accel_[1];
      if (a1.t_ns - a0.t_ns > max_gap_ns_) {
        drop(g, "in a " + std::to_string((a1.t_ns - a0.t_ns) / 1'000'000) +
                    " ms gap of the accelerometer");
        gyro_.pop_front();
        continue;
      }
      const double s =
          static_cast<double>(g.t_ns - a0.t_ns) / static_cast<double>(a1.t_ns - a0.t_ns);
      out->push_back({g.t_ns, g.gyro, (1.0 - s) * a0.accel + s * a1.accel});
    }
    ++counters_.paired;
    gyro_.pop_front();
  }
}

void ImuPairer::restart() {
  accel_.clear();
  gyro_.clear();
}

}  // namespace hs
