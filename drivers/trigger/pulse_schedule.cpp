#include "drivers/trigger/pulse_schedule.h"

#include <cmath>

namespace hs {

PulseSchedule::PulseSchedule(int64_t start_ns, double rate_hz)
    : start_ns_(start_ns), rate_hz_(rate_hz), period_ns_(std::llround(1e9 / rate_hz)) {}

int64_t PulseSchedule::deadline(int64_t k) const {
  return start_ns_ + std::llround(static_cast<double>(k) * 1e9 / rate_hz_);
}

int64_t PulseSchedule::next(int64_t now_ns) {
  while (deadline(k_) + period_ns_ <= now_ns) {  // a whole period late: that pulse is gone
    ++k_;
    ++skipped_;
  }
  return deadline(k_++);
}

bool SyncDivider::edges(int pending) {
  bool due = false;
  for (int i = 0; i < pending; ++i) {
    if (count_++ % divider_ != 0) continue;
    due = true;
    if (i + 1 < pending) ++late_;
  }
  return due;
}

}  // namespace hs
