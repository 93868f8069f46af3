#pragma once
// Sub-pixel refinement of a stereo match on a slanted surface. A window matched by translation
// alone takes the disparity where its texture is strongest; on the ground ahead the texture
// fades towards the horizon, so the nearer rows win and the disparity comes out too large (on
// the simulated street with a 15 px window, +0.018 px nearer than 7.6 m and +0.06 px at
// 7.6-14 m: the whole trajectory shrinks and sinks). A plane's disparity is affine in the pixel, so the refinement lets it vary
// across the window along the epipolar direction: cam1 pixel = uv1 + t + o + e * (a*o.x +
// b*o.y) for window offset o, with an affine brightness change, by Gauss-Newton.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>

namespace hs {

struct SlantedRefineOptions {
  int half_window = 7;  // (2 * half_window + 1)^2 samples
  int max_iterations = 5;
  double convergence_px = 1e-3;  // step of the centre
  double max_shift_px = 1.0;     // from the starting match; further: not refined
  double max_slant = 0.5;        // |a|, |b| (disparity change per pixel); more: not refined
  double min_gradient = 1.0;     // grey levels per pixel (RMS, weakest direction): texture
};

// cam1's image as the refinement samples it: intensity and central-difference gradients
// (float), built once per image pair.
struct SlantedRefineImage {
  explicit SlantedRefineImage(const cv::Mat& image1);  // CV_8UC1
  cv::Mat value, gx, gy;                               // CV_32FC1
};

struct SlantedMatch {
  Eigen::Vector2d uv1 = Eigen::Vector2d::Zero();  // cam1 pixel matching uv0
  double a = 0.0, b = 0.0;  // cam1 shift along e per pixel of cam0 offset in u and in v
};

// uv0: cam0 pixel; uv1: its match in cam1 (e.g. from optical flow); e: unit direction along
// which the cam1 pixel moves with disparity (the epipolar line at uv1). image0 CV_8UC1.
// Returns the refined match at uv0, or nullopt when the refinement is not trustworthy
// (out of the image, textureless, moved too far or too slanted).
std::optional<SlantedMatch> refine_slanted_match(
    const cv::Mat& image0, const SlantedRefineImage& image1, const Eigen::Vector2d& uv0,
    const Eigen::Vector2d& uv1, const Eigen::Vector2d& e, const SlantedRefineOptions& options);

}  // namespace hs
