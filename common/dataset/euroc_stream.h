#pragma once
// A dataset replayed in process: IMU samples, ground truth and frames merged in sensor-time
// order. Deterministic; at equal timestamps IMU comes first, then ground truth, then the frame,
// so the IMU sample at a frame's time is available when the frame arrives.
#include <variant>
#include <vector>

#include "common/dataset/euroc_reader.h"

namespace hs {

using DatasetEvent = std::variant<ImuSample, NavState, StereoFrame>;

class EurocStream {
 public:
  explicit EurocStream(const EurocReader& reader);  // `reader` must outlive the stream

  // Next event; false at the end. A frame's images are loaded here (InputError if bad).
  bool next(DatasetEvent& event);
  size_t size() const { return order_.size(); }
  size_t position() const { return position_; }

 private:
  enum class Kind { kImu, kGroundTruth, kFrame };  // tie-break order at equal timestamps
  struct Ref {
    int64_t t_ns;
    Kind kind;
    size_t index;
  };

  const EurocReader& reader_;
  std::vector<Ref> order_;
  size_t position_ = 0;
};

}  // namespace hs
