#pragma once
// Collects the poses published on one channel (odometry_t or ground_truth_t, told apart by the
// message fingerprint) and counts the messages heard on every channel; writes a TUM trajectory.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/core/types.h"

namespace hs {

class PoseRecorder {
 public:
  explicit PoseRecorder(std::string channel) : channel_(std::move(channel)) {}

  // Any message heard. Messages on the recorded channel that do not decode as odometry_t or
  // ground_truth_t are counted as rejected with the reason kept (never silently used).
  void handle(const std::string& channel, const void* data, size_t size);

  const std::string& channel() const { return channel_; }
  const std::vector<NavState>& poses() const { return poses_; }
  const std::map<std::string, int64_t>& counts() const { return counts_; }
  int64_t rejected() const { return rejected_; }
  const std::string& first_error() const { return first_error_; }
  // Message type seen on the recorded channel ("" before the first valid message).
  const std::string& type_name() const { return type_name_; }

  // Writes "t[s] x y z qx qy qz qw" lines in time order, atomically. Returns how many poses were
  // out of order on arrival (they are sorted; the count is for the report).
  size_t write_tum(const std::string& path) const;

 private:
  std::string channel_;
  std::vector<NavState> poses_;
  std::map<std::string, int64_t> counts_;
  int64_t rejected_ = 0;
  std::string first_error_;
  std::string type_name_;
};

}  // namespace hs
