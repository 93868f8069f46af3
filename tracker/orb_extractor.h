#pragma once
// ORB keypoints and descriptors, only ever computed for keyframes (and for relocalisation),
// spread over the image by a grid so that pose estimation sees the whole field of view.
#include <Eigen/Core>
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
  Eigen::Vector2d uv(size_t i) const { return {keypoints[i].pt.x, keypoints[i].pt.y}; }
};

class OrbExtractor {
 public:
  explicit OrbExtractor(const OrbOptions& options);
  OrbFeatures extract(const cv::Mat& image) const { return describe(image, detect(image)); }
  // Keypoints only, spread by the grid.
  std::vector<cv::KeyPoint> detect(const cv::Mat& image) const;
  // Descriptors of given keypoints (octave and angle as set). Keypoints too close to the border
  // for a descriptor are dropped; the others come back unchanged but grouped by octave (the
  // caller can tell them apart by class_id, which is kept).
  OrbFeatures describe(const cv::Mat& image, std::vector<cv::KeyPoint> keypoints) const;
  // Both work on the scale pyramid in two halves of about equal area, the finest levels and the
  // rest on a downscaled image, which run in parallel (cv::parallel_for_). The results do not
  // depend on the thread count, and are those of one cv::ORB pyramid except that the coarse
  // levels' sizes are rounded from the downscaled image (a pixel off from two levels past the
  // split on: the same corners, descriptors a few bits apart).
  const OrbOptions& options() const { return options_; }

 private:
  // Keypoints of levels [0, split_level_) on `image` and of [split_level_, num_levels) on the
  // image downscaled to split_level_, in full-resolution pixels with octaves of the whole pyramid.
  std::vector<cv::KeyPoint> detect_candidates(const cv::Mat& image) const;
  // `image` at pyramid level split_level_, and that level's scale.
  cv::Mat coarse_image(const cv::Mat& image, float* scale) const;

  OrbOptions options_;
  cv::Ptr<cv::ORB> orb_;         // the whole pyramid (descriptors)
  cv::Ptr<cv::ORB> orb_fine_;    // levels below split_level_ (null when there is no split)
  cv::Ptr<cv::ORB> orb_coarse_;  // levels from split_level_ on, on the downscaled image
  int split_level_ = 0;
};

// Scale of a keypoint's octave relative to level 0.
inline float octave_scale(const OrbOptions& options, int octave) {
  float s = 1.0f;
  for (int i = 0; i < octave; ++i) s *= options.scale_factor;
  return s;
}

}  // namespace hs
