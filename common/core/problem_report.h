#pragma once
// A driver's current problem (a device missing, lost or busy, the last bad input): said once on
// stderr (the journal) each time it changes, kept for HEARTBEAT's message, and "recent" for a hold
// time after it was last set, which is how long HEARTBEAT stays DEGRADED after bad input.
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>

namespace hs {

class ProblemReport {
 public:
  explicit ProblemReport(std::string process) : process_(std::move(process)) {}

  void set(std::string problem, int64_t now_ns) {
    set_ns_ = now_ns;
    if (problem == text_) return;
    text_ = std::move(problem);
    std::fprintf(stderr, "%s: %s\n", process_.c_str(), text_.c_str());
  }
  void clear() {
    text_.clear();
    set_ns_ = -1;
  }
  const std::string& text() const { return text_; }
  bool empty() const { return text_.empty(); }
  bool recent(int64_t now_ns, int64_t hold_ns) const {
    return set_ns_ >= 0 && now_ns - set_ns_ < hold_ns;
  }

 private:
  std::string process_;
  std::string text_;
  int64_t set_ns_ = -1;
};

}  // namespace hs
