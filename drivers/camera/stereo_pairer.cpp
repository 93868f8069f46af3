#include "drivers/camera/stereo_pairer.h"

#include <cstdlib>

namespace hs {

StereoPairer::StereoPairer(int64_t max_difference_ns, size_t max_waiting)
    : max_difference_ns_(max_difference_ns), max_waiting_(max_waiting) {}

void StereoPairer::reset() {
  waiting_[0].clear();
  waiting_[1].clear();
  seq_offset_.reset();
}

std::vector<std::pair<SideFrame, SideFrame>> StereoPairer::add(int side, const SideFrame& frame,
                                                               std::vector<SideFrame>* dropped) {
  std::deque<SideFrame>& mine = waiting_[side];
  mine.push_back(frame);
  if (mine.size() > max_waiting_) {  // the other device is silent: do not hoard images
    dropped->push_back(mine.front());
    ++(side == 0 ? stats_.unpaired_left : stats_.unpaired_right);
    mine.pop_front();
  }
  std::vector<std::pair<SideFrame, SideFrame>> pairs;
  std::deque<SideFrame>& left = waiting_[0];
  std::deque<SideFrame>& right = waiting_[1];
  while (!left.empty() && !right.empty()) {
    const SideFrame& l = left.front();
    const SideFrame& r = right.front();
    const int64_t d = l.t_ns - r.t_ns;
    if (std::llabs(d) <= max_difference_ns_) {
      const int64_t offset = static_cast<int64_t>(r.seq) - static_cast<int64_t>(l.seq);
      if (seq_offset_ && *seq_offset_ != offset) ++stats_.sequence_offset_changes;
      seq_offset_ = offset;
      pairs.emplace_back(l, r);
      ++stats_.pairs;
      left.pop_front();
      right.pop_front();
    } else if (d < 0) {  // the left one is older than anything the right side will send
      dropped->push_back(l);
      ++stats_.unpaired_left;
      left.pop_front();
    } else {
      dropped->push_back(r);
      ++stats_.unpaired_right;
      right.pop_front();
    }
  }
  return pairs;
}

}  // namespace hs
