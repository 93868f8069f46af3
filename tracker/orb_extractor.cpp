#include "tracker/orb_extractor.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

namespace hs {

namespace {

constexpr int kEdgeThreshold = 19;
constexpr int kPatchSize = 31;

cv::Ptr<cv::ORB> make_orb(const OrbOptions& o, int num_features, int num_levels) {
  return cv::ORB::create(num_features, o.scale_factor, num_levels, kEdgeThreshold,
                         /*firstLevel=*/0, /*WTA_K=*/2, cv::ORB::FAST_SCORE, kPatchSize,
                         o.fast_threshold);
}

}  // namespace

OrbExtractor::OrbExtractor(const OrbOptions& options) : options_(options) {
  // Over-detect, then keep the strongest per grid cell: cv::ORB alone clusters its budget on
  // the most textured region.
  const int candidates = options.num_features * 3;
  orb_ = make_orb(options, candidates, options.num_levels);
  // FAST over the pyramid is most of the detection time; level l has area f^l (f = 1/s^2), so
  // the first levels whose area reaches half the total run beside the rest. cv::ORB shares its
  // budget between levels in proportion to 1/s^l, and each half gets its levels' share.
  const double f = 1.0 / (options.scale_factor * options.scale_factor);
  const double total_area = (1.0 - std::pow(f, options.num_levels)) / (1.0 - f);
  double area = 0.0;
  int split = 0;
  while (split < options.num_levels - 1 && area < 0.5 * total_area) area += std::pow(f, split++);
  if (split < 1 || split >= options.num_levels) return;
  split_level_ = split;
  const double g = 1.0 / options.scale_factor;
  const double fine_share = (1.0 - std::pow(g, split)) / (1.0 - std::pow(g, options.num_levels));
  const int fine = static_cast<int>(std::lround(candidates * fine_share));
  orb_fine_ = make_orb(options, fine, split);
  orb_coarse_ = make_orb(options, candidates - fine, options.num_levels - split);
}

cv::Mat OrbExtractor::coarse_image(const cv::Mat& image, float* scale) const {
  // The same chain of resizes as cv::ORB's own pyramid, so the coarse levels see the same
  // pixels as they would in one pyramid.
  cv::Mat level = image;
  *scale = 1.f;
  for (int l = 0; l < split_level_; ++l) {
    *scale *= options_.scale_factor;
    cv::Mat next;
    cv::resize(level, next, cv::Size(cvRound(image.cols / *scale), cvRound(image.rows / *scale)), 0,
               0, cv::INTER_LINEAR_EXACT);
    level = next;
  }
  return level;
}

std::vector<cv::KeyPoint> OrbExtractor::detect_candidates(const cv::Mat& image) const {
  std::vector<cv::KeyPoint> fine, coarse;
  if (!orb_fine_) {
    orb_->detect(image, fine);
    return fine;
  }
  cv::parallel_for_(cv::Range(0, 2), [&](const cv::Range& range) {
    for (int task = range.start; task < range.end; ++task) {
      if (task == 0) {
        orb_fine_->detect(image, fine);
        continue;
      }
      float scale = 1.f;
      orb_coarse_->detect(coarse_image(image, &scale), coarse);
      for (cv::KeyPoint& kp : coarse) {
        kp.pt *= scale;
        kp.size *= scale;
        kp.octave += split_level_;
      }
    }
  });
  fine.insert(fine.end(), coarse.begin(), coarse.end());
  return fine;
}

std::vector<cv::KeyPoint> OrbExtractor::detect(const cv::Mat& image) const {
  const std::vector<cv::KeyPoint> candidates = detect_candidates(image);

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
    std::stable_sort(cell.begin(), cell.end(),
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
  if (keypoints.empty()) return out;
  if (!orb_fine_) {
    orb_->compute(image, keypoints, out.descriptors);
    out.keypoints = std::move(keypoints);
    return out;
  }
  // Each half describes its octaves on its own pyramid; class_id carries the input index
  // through cv::ORB (which drops and regroups keypoints), so the survivors come back exactly
  // as given.
  std::vector<cv::KeyPoint> half[2];
  for (size_t i = 0; i < keypoints.size(); ++i) {
    cv::KeyPoint kp = keypoints[i];
    kp.class_id = static_cast<int>(i);
    half[kp.octave >= split_level_ ? 1 : 0].push_back(kp);
  }
  cv::Mat descriptors[2];
  cv::parallel_for_(cv::Range(0, 2), [&](const cv::Range& range) {
    for (int h = range.start; h < range.end; ++h) {
      if (half[h].empty()) continue;
      if (h == 0) {
        orb_fine_->compute(image, half[0], descriptors[0]);
        continue;
      }
      float scale = 1.f;
      const cv::Mat coarse = coarse_image(image, &scale);
      for (cv::KeyPoint& kp : half[1]) {
        kp.pt /= scale;
        kp.size /= scale;
        kp.octave -= split_level_;
      }
      orb_coarse_->compute(coarse, half[1], descriptors[1]);
    }
  });
  for (const std::vector<cv::KeyPoint>& kps : half)
    for (const cv::KeyPoint& kp : kps) out.keypoints.push_back(keypoints[kp.class_id]);
  if (descriptors[0].empty() || descriptors[1].empty())
    out.descriptors = descriptors[0].empty() ? descriptors[1] : descriptors[0];
  else
    cv::vconcat(descriptors[0], descriptors[1], out.descriptors);
  return out;
}

}  // namespace hs
