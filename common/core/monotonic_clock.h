#pragma once
// Host clocks in int64 nanoseconds: CLOCK_MONOTONIC (heartbeat_t.t_ns, heartbeat scheduling) and
// this thread's CPU time (stage and benchmark figures that stay meaningful on a loaded machine).
#include <time.h>

#include <cstdint>

namespace hs {

inline int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

inline int64_t thread_cpu_ns() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}
inline double thread_cpu_s() {
  return 1e-9 * static_cast<double>(thread_cpu_ns());
}

}  // namespace hs
