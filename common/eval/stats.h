#pragma once
// Summary statistics of an error series, as evo reports them (numpy semantics: std is the
// population standard deviation, ddof = 0; median averages the two middle values).
#include <cstddef>
#include <vector>

namespace hs {

struct Stats {
  double rmse = 0, mean = 0, median = 0, std = 0, min = 0, max = 0, sse = 0;
  size_t count = 0;
};

// Throws InputError on an empty series.
Stats compute_stats(const std::vector<double>& values);

}  // namespace hs
