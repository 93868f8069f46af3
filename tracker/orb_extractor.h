#pragma once
// ORB keypoints and descriptors, only ever computed for keyframes (and for relocalisation),
// spread over the image by a grid so that pose estimation sees the whole field of view.
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <vector>

namespace hs {

struct OrbOptions {
  int num_features = 1000;
  float scale_factor = 1.2f;
  int num_levels = 8;
  int fast_threshold = 12;
  int grid_cols = 16;  // the budget is shared evenly between grid cells
  int grid_rows = 10;
};

struct OrbFeatures {
  std::vector<cv::KeyPoint> keypoints;  // distorted pixels of the full-resolution image
  cv::Mat descriptors;                  // rows x 32, CV_8U
  size_t size() const { return keypoints.size(); }
};

class OrbExtractor {
 public:
  explicit OrbExtractor(const OrbOptions& options);
  OrbFeatures extract(const cv::Mat& image) const { return describe(image, detect(image)); }
  // Keypoints only, spread by the grid.
  std::vector<cv::KeyPoint> detect(const cv::Mat& image) const;
  // Descriptors of given keypoints (octave and angle as set). Keypoints too close to the border
  // for a descriptor are dropped; the others keep their order.
  OrbFeatures describe(const cv::Mat& image, std::vector<cv::KeyPoint> keypoints) const;
  const OrbOptions& options() const { return options_; }

 private:
  OrbOptions options_;
  cv::Ptr<cv::ORB> orb_;
};

// Scale of a keypoint's octave relative to level 0.
inline float octave_scale(const OrbOptions& options, int octave) {
  float s = 1.0f;
  for (int i = 0; i < octave; ++i) s *= options.scale_factor;
  return s;
}

}  // namespace hs
