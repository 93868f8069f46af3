#include "tracker/orb_extractor.h"

#include <algorithm>

namespace hs {

OrbExtractor::OrbExtractor(const OrbOptions& options) : options_(options) {
  // Over-detect, then keep the strongest per grid cell: cv::ORB alone clusters its budget on
  // the most textured region.
  orb_ = cv::ORB::create(options.num_features * 3, options.scale_factor, options.num_levels,
                         /*edgeThreshold=*/19, /*firstLevel=*/0, /*WTA_K=*/2, cv::ORB::FAST_SCORE,
                         /*patchSize=*/31, options.fast_threshold);
}

std::vector<cv::KeyPoint> OrbExtractor::detect(const cv::Mat& image) const {
  std::vector<cv::KeyPoint> candidates;
  orb_->detect(image, candidates);

  const int cells = options_.grid_cols * options_.grid_rows;
  std::vector<std::vector<int>> by_cell(cells);
  for (int i = 0; i < static_cast<int>(candidates.size()); ++i) {
    const cv::Point2f& pt = candidates[i].pt;
    const int cx = std::clamp(static_cast<int>(pt.x * options_.grid_cols / image.cols), 0,
                              options_.grid_cols - 1);
    const int cy = std::clamp(static_cast<int>(pt.y * options_.grid_rows / image.rows), 0,
                              options_.grid_rows - 1);
    by_cell[cy * options_.grid_cols + cx].push_back(i);
  }
  // Round-robin over cells, strongest first, until the budget is spent: sparse cells give
  // their unused share to dense ones.
  for (auto& cell : by_cell)
    std::sort(cell.begin(), cell.end(),
              [&](int a, int b) { return candidates[a].response > candidates[b].response; });
  std::vector<cv::KeyPoint> kept;
  kept.reserve(options_.num_features);
  for (size_t rank = 0; kept.size() < static_cast<size_t>(options_.num_features); ++rank) {
    bool any = false;
    for (const auto& cell : by_cell) {
      if (rank >= cell.size()) continue;
      any = true;
      kept.push_back(candidates[cell[rank]]);
      if (kept.size() == static_cast<size_t>(options_.num_features)) break;
    }
    if (!any) break;
  }

  return kept;
}

OrbFeatures OrbExtractor::describe(const cv::Mat& image,
                                   std::vector<cv::KeyPoint> keypoints) const {
  OrbFeatures out;
  if (!keypoints.empty()) orb_->compute(image, keypoints, out.descriptors);
  out.keypoints = std::move(keypoints);
  return out;
}

}  // namespace hs
