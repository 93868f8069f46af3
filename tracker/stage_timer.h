#pragma once
// Wall time of consecutive pipeline stages of one frame, in the order they ran (the per-stage
// columns of hs-run's timing.csv and of TRACKER_STATUS).
#include <chrono>

#include "tracker/tracker_types.h"

namespace hs {

class StageTimer {
 public:
  explicit StageTimer(FrameResult& result) : result_(result), start_(Clock::now()), last_(start_) {}
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;
  // Closes the stage that started at the previous mark (or at construction).
  void stage(const char* name) {
    const auto now = Clock::now();
    result_.stage_ms.emplace_back(name, ms(last_, now));
    last_ = now;
  }
  ~StageTimer() { result_.total_ms = ms(start_, Clock::now()); }

 private:
  using Clock = std::chrono::steady_clock;
  static float ms(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<float, std::milli>(b - a).count();
  }
  FrameResult& result_;
  Clock::time_point start_, last_;
};

}  // namespace hs
