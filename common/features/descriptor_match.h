#pragma once
// Binary descriptor matching (Hamming distance on 256-bit ORB descriptors): guided search
// around predicted pixels, and mutual nearest neighbours between two descriptor sets.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

namespace hs {

int hamming256(const uint8_t* a, const uint8_t* b);

struct DescriptorMatchOptions {
  int max_distance = 60;  // accept at most this Hamming distance
  float ratio = 0.8f;     // best must beat the second best by this ratio
  double search_radius_px = 15.0;
};

// Buckets keypoint pixels into a grid for radius queries.
class KeypointGrid {
 public:
  KeypointGrid(const std::vector<Eigen::Vector2f>& uv, int width, int height, int cell_px = 32);
  // Indices of keypoints within `radius` of `centre`.
  void query(const Eigen::Vector2d& centre, double radius, std::vector<int>& out) const;

 private:
  const std::vector<Eigen::Vector2f>& uv_;
  int cell_px_, cols_, rows_;
  std::vector<std::vector<int>> cells_;
};

// For each query descriptor with a predicted pixel, the best keypoint within the search radius
// (-1 when none passes the distance and ratio tests). A keypoint is given to at most one query
// (the one with the smaller distance).
std::vector<int> match_by_projection(const cv::Mat& query_descriptors,
                                     const std::vector<Eigen::Vector2d>& predicted_uv,
                                     const cv::Mat& train_descriptors, const KeypointGrid& grid,
                                     const DescriptorMatchOptions& options);

// Mutual nearest neighbours passing the ratio test: pairs (query index, train index).
std::vector<std::pair<int, int>> match_mutual(const cv::Mat& query_descriptors,
                                              const cv::Mat& train_descriptors,
                                              const DescriptorMatchOptions& options);

}  // namespace hs
