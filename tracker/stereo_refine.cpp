#include "tracker/stereo_refine.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "tracker/direct_sampling.h"

namespace hs {
namespace {

struct Sample {
  double value, gx, gy;
};

// Bilinear interpolation of the three images at one set of weights; (x, y) inside all.
Sample sample(const SlantedRefineImage& img, double x, double y) {
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const float ax = static_cast<float>(x - x0), ay = static_cast<float>(y - y0);
  const float w00 = (1.f - ax) * (1.f - ay), w01 = ax * (1.f - ay), w10 = (1.f - ax) * ay,
              w11 = ax * ay;
  const auto at = [&](const cv::Mat& m) {
    const float* r0 = m.ptr<float>(y0) + x0;
    const float* r1 = m.ptr<float>(y0 + 1) + x0;
    return static_cast<double>(w00 * r0[0] + w01 * r0[1] + w10 * r1[0] + w11 * r1[1]);
  };
  return {at(img.value), at(img.gx), at(img.gy)};
}

}  // namespace

SlantedRefineImage::SlantedRefineImage(const cv::Mat& image1) {
  image1.convertTo(value, CV_32F);
  // Central differences: sampled bilinearly they equal the difference of bilinear samples
  // one pixel either side, the derivative the refinement needs.
  const cv::Mat k = (cv::Mat_<float>(1, 3) << -0.5f, 0.f, 0.5f);
  cv::filter2D(value, gx, CV_32F, k, cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
  cv::filter2D(value, gy, CV_32F, k.t(), cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
}

std::optional<SlantedMatch> refine_slanted_match(
    const cv::Mat& image0, const SlantedRefineImage& image1, const Eigen::Vector2d& uv0,
    const Eigen::Vector2d& uv1, const Eigen::Vector2d& e, const SlantedRefineOptions& options) {
  using direct::bilinear_inside;
  const int r = options.half_window;
  // The slant can stretch the window by max_slant * r along e.
  const double reach = r * (1.0 + options.max_slant) + options.max_shift_px + 1.0;
  const auto inside = [reach](const cv::Mat& img, const Eigen::Vector2d& uv) {
    return bilinear_inside(img, uv.x() - reach, uv.y() - reach) &&
           bilinear_inside(img, uv.x() + reach, uv.y() + reach);
  };
  if (!inside(image0, uv0) || !inside(image1.value, uv1)) return std::nullopt;

  const int n = (2 * r + 1) * (2 * r + 1);
  std::vector<Eigen::Vector2d> offsets;
  std::vector<double> tpl;
  offsets.reserve(n);
  tpl.reserve(n);
  double mean = 0.0;
  for (int y = -r; y <= r; ++y) {
    for (int x = -r; x <= r; ++x) {
      offsets.emplace_back(x, y);
      tpl.push_back(direct::sample_bilinear(image0, uv0.x() + x, uv0.y() + y));
      mean += tpl.back();
    }
  }
  mean /= n;
  for (double& t : tpl) t -= mean;  // mean-free: gain and bias decouple

  // theta = (tx, ty, a, b, gain, bias)
  Eigen::Matrix<double, 6, 1> theta;
  theta << 0, 0, 0, 0, 1, mean;
  for (int it = 0; it < options.max_iterations; ++it) {
    Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector2d& o = offsets[k];
      const Eigen::Vector2d p =
          uv1 + theta.head<2>() + o + e * (theta[2] * o.x() + theta[3] * o.y());
      const Sample s = sample(image1, p.x(), p.y());
      const double ge = s.gx * e.x() + s.gy * e.y();
      Eigen::Matrix<double, 6, 1> J;
      J << s.gx, s.gy, ge * o.x(), ge * o.y(), -tpl[k], -1.0;
      const double res = s.value - theta[4] * tpl[k] - theta[5];
      H.selfadjointView<Eigen::Lower>().rankUpdate(J);
      g.noalias() += J * res;
    }
    const Eigen::Matrix<double, 6, 6> H_full = H.selfadjointView<Eigen::Lower>();
    const double weakest = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(
                               H_full.topLeftCorner<2, 2>(), Eigen::EigenvaluesOnly)
                               .eigenvalues()[0];
    if (!(weakest >= options.min_gradient * options.min_gradient * n)) return std::nullopt;
    const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(H_full);
    if (ldlt.info() != Eigen::Success || ldlt.rcond() < 1e-9) return std::nullopt;
    const Eigen::Matrix<double, 6, 1> step = -ldlt.solve(g);
    if (!step.allFinite()) return std::nullopt;
    theta += step;
    if (theta.head<2>().norm() > options.max_shift_px ||
        std::max(std::abs(theta[2]), std::abs(theta[3])) > options.max_slant)
      return std::nullopt;
    if (step.head<2>().norm() < options.convergence_px) break;
  }
  return SlantedMatch{uv1 + theta.head<2>(), theta[2], theta[3]};
}

}  // namespace hs
