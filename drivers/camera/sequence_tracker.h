#pragma once
// Frames a V4L2 device dropped, from gaps in its buffer sequence numbers (v4l2_buffer.sequence
// counts every frame the device captured, delivered or not).
#include <cstdint>
#include <optional>

namespace hs {

struct SequenceStats {
  int64_t frames = 0;
  int64_t dropped = 0;    // sequence numbers skipped
  int64_t backwards = 0;  // a sequence number not after the previous one (frame dropped)
};

class SequenceTracker {
 public:
  // Frames missing right before this one (0: none); -1 when `seq` does not advance.
  int64_t add(uint32_t seq);
  // The device was re-opened: its sequence starts again.
  void reset() { last_.reset(); }
  const SequenceStats& stats() const { return stats_; }

 private:
  std::optional<uint32_t> last_;
  SequenceStats stats_;
};

}  // namespace hs
