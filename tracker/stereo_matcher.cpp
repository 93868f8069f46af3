#include "tracker/stereo_matcher.h"

#include <opencv2/core/utility.hpp>
#include <opencv2/video/tracking.hpp>

#include "common/geometry/triangulation.h"

namespace hs {

StereoMatcher::StereoMatcher(const StereoCalib& calib, const StereoMatchOptions& options)
    : calib_(calib),
      options_(options),
      T_c0_c1_(calib.T_c0_c1()),
      T_c1_c0_(calib.T_c0_c1().inverse()) {}

std::vector<StereoMatch> StereoMatcher::match(const cv::Mat& image0, const cv::Mat& image1,
                                              const std::vector<Eigen::Vector2d>& uv0) const {
  const PinholeRadtan& cam0 = calib_.cam0.intrinsics;
  const PinholeRadtan& cam1 = calib_.cam1.intrinsics;
  std::vector<StereoMatch> out(uv0.size());
  if (uv0.empty()) return out;

  std::vector<cv::Point2f> left, right, back;
  left.reserve(uv0.size());
  right.reserve(uv0.size());
  for (const Eigen::Vector2d& uv : uv0) {
    const Eigen::Vector3d p_c0 = cam0.unproject(uv) * options_.init_depth_m;
    Eigen::Vector2d guess = cam1.project(T_c1_c0_ * p_c0);
    left.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    right.emplace_back(static_cast<float>(guess.x()), static_cast<float>(guess.y()));
  }
  const cv::Size win(options_.window, options_.window);
  const cv::TermCriteria term(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
  // Both pyramids (with their derivatives) once, shared by the forward and the backward pass,
  // built side by side.
  std::vector<cv::Mat> pyr0, pyr1;
  const int max_level = options_.pyramid_levels - 1;
  cv::parallel_for_(cv::Range(0, 2), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i)
      cv::buildOpticalFlowPyramid(i == 0 ? image0 : image1, i == 0 ? pyr0 : pyr1, win, max_level);
  });
  std::vector<uint8_t> ok_fwd, ok_back;
  std::vector<float> err;
  cv::calcOpticalFlowPyrLK(pyr0, pyr1, left, right, ok_fwd, err, win, max_level, term,
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  back = left;
  cv::calcOpticalFlowPyrLK(pyr1, pyr0, right, back, ok_back, err, win, max_level, term,
                           cv::OPTFLOW_USE_INITIAL_FLOW);

  const double max_epi2 = options_.max_epipolar_px * options_.max_epipolar_px;
  for (size_t i = 0; i < uv0.size(); ++i) {
    if (!ok_fwd[i] || !ok_back[i]) continue;
    const Eigen::Vector2d uv1(right[i].x, right[i].y);
    if (!cam1.in_image(uv1, 1.0)) continue;
    if (Eigen::Vector2d(back[i].x - left[i].x, back[i].y - left[i].y).norm() >
        options_.max_backflow_px)
      continue;
    const auto p_c0 = triangulate_two_view(cam0.unproject_normalised(uv0[i]),
                                           cam1.unproject_normalised(uv1), T_c0_c1_);
    if (!p_c0 || p_c0->z() < options_.min_depth_m || p_c0->z() > options_.max_depth_m) continue;
    Eigen::Vector2d re0, re1;
    if (!cam0.project(*p_c0, &re0) || !cam1.project(T_c1_c0_ * *p_c0, &re1)) continue;
    if ((re0 - uv0[i]).squaredNorm() > max_epi2 || (re1 - uv1).squaredNorm() > max_epi2) continue;
    out[i] = {true, uv1, *p_c0};
  }
  return out;
}

}  // namespace hs
