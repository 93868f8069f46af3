#include "tracker/imu_buffer.h"

#include <algorithm>
#include <climits>
#include <cmath>

namespace hs {

const char* to_string(ImuReject reason) {
  switch (reason) {
    case ImuReject::kAccepted:
      return "accepted";
    case ImuReject::kNonFinite:
      return "non-finite IMU value";
    case ImuReject::kOutOfRange:
      return "IMU value out of range";
    case ImuReject::kOutOfOrder:
      return "IMU timestamp older than the previous sample";
    case ImuReject::kDuplicate:
      return "duplicate IMU timestamp";
  }
  return "?";
}

ImuReject ImuBuffer::push(const ImuSample& s) {
  ImuReject reason = ImuReject::kAccepted;
  if (!s.gyro.allFinite() || !s.accel.allFinite()) {
    reason = ImuReject::kNonFinite;
    ++counters_.non_finite;
  } else if (s.gyro.cwiseAbs().maxCoeff() > options_.max_gyro_rad_s ||
             s.accel.cwiseAbs().maxCoeff() > options_.max_accel_m_s2) {
    reason = ImuReject::kOutOfRange;
    ++counters_.out_of_range;
  } else if (!samples_.empty() && s.t_ns == samples_.back().t_ns) {
    reason = ImuReject::kDuplicate;
    ++counters_.duplicate;
  } else if (!samples_.empty() && s.t_ns < samples_.back().t_ns) {
    reason = ImuReject::kOutOfOrder;
    ++counters_.out_of_order;
  }
  if (reason != ImuReject::kAccepted) return reason;
  ++counters_.accepted;
  samples_.push_back(s);
  while (samples_.size() > 2 && samples_.front().t_ns < s.t_ns - options_.keep_ns)
    samples_.pop_front();
  return reason;
}

std::vector<ImuSample> ImuBuffer::window(int64_t t0_ns, int64_t t1_ns) const {
  const auto by_time = [](const ImuSample& a, int64_t t) { return a.t_ns < t; };
  auto first = std::lower_bound(samples_.begin(), samples_.end(), t0_ns, by_time);
  auto last = std::lower_bound(samples_.begin(), samples_.end(), t1_ns, by_time);
  if (first != samples_.begin()) --first;  // one sample before t0 for interpolation
  if (last != samples_.end()) ++last;      // include the sample at/after t1
  return {first, last};
}

}  // namespace hs
