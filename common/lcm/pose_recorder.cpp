#include "common/lcm/pose_recorder.h"

#include <algorithm>
#include <cinttypes>
#include <cstdio>

#include "common/core/atomic_file.h"
#include "common/core/error.h"
#include "common/lcm/convert.h"
#include "common/lcm/decode.h"

namespace hs {

void PoseRecorder::handle(const std::string& channel, const void* data, size_t size) {
  ++counts_[channel];
  if (channel != channel_) return;
  try {
    const int64_t fingerprint = message_fingerprint(data, size);
    NavState x;
    std::string type;
    if (fingerprint == hsslam::odometry_t::getHash()) {
      x = odometry_from_msg(decode_message<hsslam::odometry_t>(data, size, channel), channel);
      type = hsslam::odometry_t::getTypeName();
    } else if (fingerprint == hsslam::ground_truth_t::getHash()) {
      x = ground_truth_from_msg(decode_message<hsslam::ground_truth_t>(data, size, channel),
                                channel);
      type = hsslam::ground_truth_t::getTypeName();
    } else {
      throw InputError(channel, "message is neither odometry_t nor ground_truth_t");
    }
    if (!type_name_.empty() && type != type_name_)
      throw InputError(channel, type + " mixed with " + type_name_ + " on one channel");
    type_name_ = type;
    poses_.push_back(x);
  } catch (const InputError& e) {
    if (rejected_++ == 0) first_error_ = e.what();
  }
}

size_t PoseRecorder::write_tum(const std::string& path) const {
  std::vector<NavState> sorted = poses_;
  size_t out_of_order = 0;
  for (size_t i = 1; i < poses_.size(); ++i)
    if (poses_[i].t_ns < poses_[i - 1].t_ns) ++out_of_order;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const NavState& a, const NavState& b) { return a.t_ns < b.t_ns; });
  AtomicFile file(path);
  char line[256];
  for (const NavState& x : sorted) {
    // Seconds printed from integer ns so no precision is lost (a double holds ~7 decimals here).
    const int64_t s = x.t_ns / 1000000000, ns = x.t_ns % 1000000000;
    std::snprintf(line, sizeof(line),
                  "%s%" PRId64 ".%09" PRId64 " %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n",
                  x.t_ns < 0 && s == 0 ? "-" : "", s, ns < 0 ? -ns : ns, x.p_w_b.x(), x.p_w_b.y(),
                  x.p_w_b.z(), x.q_w_b.x(), x.q_w_b.y(), x.q_w_b.z(), x.q_w_b.w());
    file.stream() << line;
  }
  file.commit();
  return out_of_order;
}

}  // namespace hs
