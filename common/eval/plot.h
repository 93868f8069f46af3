#pragma once
// PNG figure of an evaluation: top view (x-y) of the aligned estimate over the ground truth,
// and the APE over time with its rmse / mean / median.
#include <string>

#include "common/eval/evaluate.h"

namespace hs {

// Written atomically; throws InputError if the image cannot be encoded or written.
void write_plot(const std::string& path, const EvalResult& result, const std::string& title);

}  // namespace hs
