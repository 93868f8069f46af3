#pragma once
// Validated, time-ordered IMU samples for the tracker. Every rejected sample is counted by
// reason, never silently used.
#include <cstdint>
#include <deque>
#include <vector>

#include "common/core/types.h"

namespace hs {

struct ImuBufferOptions {
  double max_gyro_rad_s = 35.0;     // ~2000 deg/s: beyond any MEMS range, so a corrupt value
  double max_accel_m_s2 = 160.0;    // ~16 g
  int64_t keep_ns = 5'000'000'000;  // history kept for preintegration and relocalisation
};

enum class ImuReject { kAccepted, kNonFinite, kOutOfRange, kOutOfOrder, kDuplicate };
const char* to_string(ImuReject reason);

struct ImuBufferCounters {
  int64_t accepted = 0;
  int64_t non_finite = 0;
  int64_t out_of_range = 0;
  int64_t out_of_order = 0;
  int64_t duplicate = 0;
};

class ImuBuffer {
 public:
  explicit ImuBuffer(const ImuBufferOptions& options = {}) : options_(options) {}

  ImuReject push(const ImuSample& sample);
  // Samples covering [t0_ns, t1_ns]: those inside plus the nearest one outside on each side
  // (so the window ends can be interpolated).
  std::vector<ImuSample> window(int64_t t0_ns, int64_t t1_ns) const;
  bool empty() const { return samples_.empty(); }
  int64_t latest_t_ns() const { return samples_.empty() ? INT64_MIN : samples_.back().t_ns; }
  const ImuBufferCounters& counters() const { return counters_; }

 private:
  ImuBufferOptions options_;
  std::deque<ImuSample> samples_;
  ImuBufferCounters counters_;
};

}  // namespace hs
