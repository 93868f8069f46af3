#pragma once
// A synchronised camera frame as the processes see it (decoded, mono8).
#include <cstdint>
#include <opencv2/core/mat.hpp>

namespace hs {

struct StereoFrame {
  int64_t t_ns = 0;  // sensor time (EuRoC: mid-exposure)
  int64_t seq = 0;   // 0, 1, 2, ... in stream order
  cv::Mat cam0;      // left, CV_8UC1
  cv::Mat cam1;      // right, CV_8UC1; empty for a mono rig
  bool stereo() const { return !cam1.empty(); }
};

}  // namespace hs
