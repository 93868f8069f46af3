#pragma once
// Host CLOCK_MONOTONIC in int64 nanoseconds (heartbeat_t.t_ns, heartbeat scheduling).
#include <time.h>

#include <cstdint>

namespace hs {

inline int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

}  // namespace hs
