#include "common/dataset/euroc_stream.h"

#include <algorithm>
#include <tuple>

namespace hs {

EurocStream::EurocStream(const EurocReader& reader) : reader_(reader) {
  order_.reserve(reader.imu().size() + reader.ground_truth().size() + reader.frames().size());
  for (size_t i = 0; i < reader.imu().size(); ++i)
    order_.push_back({reader.imu()[i].t_ns, Kind::kImu, i});
  for (size_t i = 0; i < reader.ground_truth().size(); ++i)
    order_.push_back({reader.ground_truth()[i].t_ns, Kind::kGroundTruth, i});
  for (size_t i = 0; i < reader.frames().size(); ++i)
    order_.push_back({reader.frames()[i].t_ns, Kind::kFrame, i});
  std::sort(order_.begin(), order_.end(), [](const Ref& a, const Ref& b) {
    return std::tie(a.t_ns, a.kind, a.index) < std::tie(b.t_ns, b.kind, b.index);
  });
}

bool EurocStream::next(DatasetEvent& event) {
  if (position_ == order_.size()) return false;
  const Ref& ref = order_[position_];
  switch (ref.kind) {
    case Kind::kImu:
      event = reader_.imu()[ref.index];
      break;
    case Kind::kGroundTruth:
      event = reader_.ground_truth()[ref.index];
      break;
    case Kind::kFrame:
      event = reader_.load_frame(ref.index);
      break;
  }
  ++position_;
  return true;
}

}  // namespace hs
