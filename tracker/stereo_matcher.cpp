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

std::optional<Eigen::Vector3d> StereoMatcher::triangulate(const Eigen::Vector2d& uv0,
                                                          const Eigen::Vector2d& uv1) const {
  return triangulate_two_view(calib_.cam0.intrinsics.unproject_normalised(uv0),
                              calib_.cam1.intrinsics.unproject_normalised(uv1), T_c0_c1_);
}

Eigen::Vector3d StereoMatcher::surface_normal(const Eigen::Vector2d& uv0, const SlantedMatch& m,
                                              const Eigen::Vector2d& e) const {
  // Three points of the surface: the match and the window's edge to the right and below.
  const double r = options_.slanted.half_window;
  const auto p0 = triangulate(uv0, m.uv1);
  const auto pu =
      triangulate(uv0 + Eigen::Vector2d(r, 0), m.uv1 + Eigen::Vector2d(r, 0) + e * (m.a * r));
  const auto pv =
      triangulate(uv0 + Eigen::Vector2d(0, r), m.uv1 + Eigen::Vector2d(0, r) + e * (m.b * r));
  if (!p0 || !pu || !pv) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d n = (*pu - *p0).cross(*pv - *p0);
  return n.norm() > 0.0 && n.allFinite() ? Eigen::Vector3d(n.normalized())
                                         : Eigen::Vector3d::Zero();
}

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

  const std::optional<SlantedRefineImage> slanted_image =
      options_.refine_slanted ? std::optional<SlantedRefineImage>(image1) : std::nullopt;
  const double max_epi2 = options_.max_epipolar_px * options_.max_epipolar_px;
  // Points are matched independently (each in its own slot): split over the cores.
  const auto match_one = [&](size_t i) -> StereoMatch {
    if (!ok_fwd[i] || !ok_back[i]) return {};
    Eigen::Vector2d uv1(right[i].x, right[i].y);
    if (!cam1.in_image(uv1, 1.0)) return {};
    if (Eigen::Vector2d(back[i].x - left[i].x, back[i].y - left[i].y).norm() >
        options_.max_backflow_px)
      return {};
    auto p_c0 = triangulate(uv0[i], uv1);
    Eigen::Vector3d n_c0 = Eigen::Vector3d::Zero();
    if (p_c0 && options_.refine_slanted && p_c0->z() > 0.0) {
      // The epipolar direction at the match: where cam1 sees cam0's ray a little nearer.
      const Eigen::Vector2d e =
          cam1.project(T_c1_c0_ * (0.95 * *p_c0)) - cam1.project(T_c1_c0_ * (1.05 * *p_c0));
      const Eigen::Vector2d e_dir = e.normalized();
      const auto refined = e.norm() > 1e-6 ? refine_slanted_match(image0, *slanted_image, uv0[i],
                                                                  uv1, e_dir, options_.slanted)
                                           : std::nullopt;
      if (refined) {
        uv1 = refined->uv1;
        p_c0 = triangulate(uv0[i], uv1);
        n_c0 = surface_normal(uv0[i], *refined, e_dir);
      }
    }
    if (!p_c0 || p_c0->z() < options_.min_depth_m || p_c0->z() > options_.max_depth_m) return {};
    Eigen::Vector2d re0, re1;
    if (!cam0.project(*p_c0, &re0) || !cam1.project(T_c1_c0_ * *p_c0, &re1)) return {};
    if ((re0 - uv0[i]).squaredNorm() > max_epi2 || (re1 - uv1).squaredNorm() > max_epi2) return {};
    return {true, uv1, *p_c0, n_c0};
  };
  cv::parallel_for_(cv::Range(0, static_cast<int>(uv0.size())), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i) out[i] = match_one(static_cast<size_t>(i));
  });
  return out;
}

}  // namespace hs
