#include "common/eval/stats.h"

#include <algorithm>
#include <cmath>

#include "common/core/error.h"

namespace hs {

Stats compute_stats(const std::vector<double>& values) {
  if (values.empty()) throw InputError("statistics of an empty error series");
  Stats s;
  s.count = values.size();
  const double n = static_cast<double>(values.size());
  double sum = 0.0;
  for (double v : values) {
    sum += v;
    s.sse += v * v;
  }
  s.mean = sum / n;
  s.rmse = std::sqrt(s.sse / n);
  double var = 0.0;
  for (double v : values) var += (v - s.mean) * (v - s.mean);
  s.std = std::sqrt(var / n);
  std::vector<double> sorted = values;
  std::sort(sorted.begin(), sorted.end());
  s.min = sorted.front();
  s.max = sorted.back();
  const size_t mid = sorted.size() / 2;
  s.median = sorted.size() % 2 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
  return s;
}

}  // namespace hs
