#pragma once
// Left and right frames of two devices paired by time (each side's frames arrive in time order):
// a pair when their times differ by at most max_difference; a frame with no partner (the other
// device dropped it) is counted and dropped once the other side has moved past it. The devices'
// sequence offset is learnt from the first pair; a pair with another offset is counted (one side
// skipped frames) but still paired by time.
#include <cstdint>
#include <deque>
#include <optional>
#include <utility>
#include <vector>

namespace hs {

struct SideFrame {
  uint32_t seq = 0;  // the device's buffer sequence
  int64_t t_ns = 0;  // mid-exposure, CLOCK_MONOTONIC
  size_t index = 0;  // the caller's handle for its image
};

struct StereoPairStats {
  int64_t pairs = 0;
  int64_t unpaired_left = 0, unpaired_right = 0;
  int64_t sequence_offset_changes = 0;
};

class StereoPairer {
 public:
  explicit StereoPairer(int64_t max_difference_ns, size_t max_waiting = 8);

  // side 0: left, 1: right. Returns the pairs completed (left, right) and appends the frames
  // given up to `dropped` (so the caller can free their images).
  std::vector<std::pair<SideFrame, SideFrame>> add(int side, const SideFrame& frame,
                                                   std::vector<SideFrame>* dropped);
  void reset();  // a device re-opened: sequences restart
  const StereoPairStats& stats() const { return stats_; }

 private:
  int64_t max_difference_ns_;
  size_t max_waiting_;
  std::deque<SideFrame> waiting_[2];
  std::optional<int64_t> seq_offset_;  // right seq - left seq
  StereoPairStats stats_;
};

}  // namespace hs
