#pragma once
// The wall-clock time now as text (strftime format), for file names and human-readable output.
// Timestamps of data are never wall-clock (see monotonic_clock.h and the message contract).
#include <ctime>
#include <string>

namespace hs {

enum class TimeZone { kUtc, kLocal };

inline std::string wall_clock_text(const char* format, TimeZone zone) {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  if (zone == TimeZone::kUtc)
    gmtime_r(&t, &tm);
  else
    localtime_r(&t, &tm);
  char buf[64];
  return std::strftime(buf, sizeof buf, format, &tm) ? buf : "";
}

}  // namespace hs
