#pragma once
// The hand-over from the LCM receive thread to the tracking thread: IMU batches, frames and
// mapper corrections in arrival order (the log sends a frame's IMU before the frame, so the
// tracker sees every sample that arrived before it). At most `max_frames` frames wait; a new
// frame then replaces the OLDEST waiting frame, whose IMU samples stay. IMU samples and
// corrections are never dropped.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <variant>
#include <vector>

#include "common/core/map_correction.h"
#include "common/core/reloc_answer.h"
#include "common/core/types.h"
#include "common/dataset/stereo_frame.h"

namespace hs {

using NodeInput = std::variant<std::vector<ImuSample>, StereoFrame, MapCorrection, RelocAnswer>;

struct InputQueueDepth {
  size_t frames = 0;
  size_t imu_samples = 0;
  size_t corrections = 0;
};

class InputQueue {
 public:
  explicit InputQueue(size_t max_frames);

  void push_imu(std::vector<ImuSample> samples);
  void push_correction(MapCorrection correction);
  void push_answer(RelocAnswer answer);  // counted with the corrections
  // Returns whether the oldest waiting frame was dropped to make room.
  bool push_frame(StereoFrame frame);
  // Blocks for the next input; false once closed and drained.
  bool pop(NodeInput& out);
  // Wakes the consumer; inputs already queued are still handed out.
  void close();
  InputQueueDepth depth() const;

 private:
  const size_t max_frames_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<NodeInput> items_;
  InputQueueDepth depth_;
  bool closed_ = false;
};

}  // namespace hs
