#include "tracker/node/input_queue.h"

#include <algorithm>
#include <stdexcept>

namespace hs {

InputQueue::InputQueue(size_t max_frames) : max_frames_(max_frames) {
  if (max_frames < 1) throw std::invalid_argument("InputQueue: max_frames must be at least 1");
}

void InputQueue::push_imu(std::vector<ImuSample> samples) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    depth_.imu_samples += samples.size();
    items_.emplace_back(std::move(samples));
  }
  ready_.notify_one();
}

void InputQueue::push_correction(MapCorrection correction) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++depth_.corrections;
    items_.emplace_back(std::move(correction));
  }
  ready_.notify_one();
}

void InputQueue::push_answer(RelocAnswer answer) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++depth_.corrections;
    items_.emplace_back(std::move(answer));
  }
  ready_.notify_one();
}

bool InputQueue::push_frame(StereoFrame frame) {
  bool dropped = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (depth_.frames >= max_frames_) {
      const auto oldest = std::find_if(items_.begin(), items_.end(), [](const NodeInput& item) {
        return std::holds_alternative<StereoFrame>(item);
      });
      items_.erase(oldest);
      --depth_.frames;
      dropped = true;
    }
    items_.emplace_back(std::move(frame));
    ++depth_.frames;
  }
  ready_.notify_one();
  return dropped;
}

bool InputQueue::pop(NodeInput& out) {
  std::unique_lock<std::mutex> lock(mutex_);
  ready_.wait(lock, [&] { return closed_ || !items_.empty(); });
  if (items_.empty()) return false;
  out = std::move(items_.front());
  items_.pop_front();
  if (const auto* imu = std::get_if<std::vector<ImuSample>>(&out))
    depth_.imu_samples -= imu->size();
  else if (std::holds_alternative<StereoFrame>(out))
    --depth_.frames;
  else
    --depth_.corrections;
  return true;
}

void InputQueue::close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
  }
  ready_.notify_all();
}

InputQueueDepth InputQueue::depth() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return depth_;
}

}  // namespace hs
