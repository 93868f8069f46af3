#include "drivers/camera/sequence_tracker.h"

namespace hs {

int64_t SequenceTracker::add(uint32_t seq) {
  if (last_ && seq <= *last_) {
    ++stats_.backwards;
    return -1;
  }
  const int64_t missing = last_ ? static_cast<int64_t>(seq) - *last_ - 1 : 0;
  last_ = seq;
  ++stats_.frames;
  stats_.dropped += missing;
  return missing;
}

}  // namespace hs
