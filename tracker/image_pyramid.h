#pragma once
// Image pyramid shared by direct alignment, optical flow and feature extraction.
// Level 0 is the full image; level k halves level k-1 (so pixel u at level 0 is at
// (u + 0.5) / 2^k - 0.5 at level k, with pixel centres at integer coordinates).
#include <opencv2/core.hpp>
#include <vector>

namespace hs {

struct ImagePyramid {
  std::vector<cv::Mat> levels;  // CV_8UC1

  int num_levels() const { return static_cast<int>(levels.size()); }
  static double scale(int level) { return 1.0 / static_cast<double>(1 << level); }
};

// Builds `num_levels` levels (>= 1) from a CV_8UC1 image by 2x2 box averaging.
ImagePyramid build_pyramid(const cv::Mat& image, int num_levels);

}  // namespace hs
