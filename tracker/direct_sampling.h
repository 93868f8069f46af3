#pragma once
// Image sampling shared by the direct alignment code (internal). Pixel centres are at integer
// coordinates (see image_pyramid.h and pinhole_radtan.h).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>

namespace hs::direct {

// Level-0 pixel -> pixel of pyramid level `level`.
inline Eigen::Vector2d to_level(const Eigen::Vector2d& uv0, int level) {
  const double s = 1.0 / static_cast<double>(1 << level);
  return {s * (uv0.x() + 0.5) - 0.5, s * (uv0.y() + 0.5) - 0.5};
}

// Pixel of pyramid level `level` -> level-0 pixel.
inline Eigen::Vector2d from_level(const Eigen::Vector2d& uv, int level) {
  const double s = static_cast<double>(1 << level);
  return {s * (uv.x() + 0.5) - 0.5, s * (uv.y() + 0.5) - 0.5};
}

// An n x n grid of samples at (x + i, y + j): all share one set of bilinear weights.
struct Grid {
  int x0 = 0, y0 = 0;    // top-left pixel
  float ax = 0, ay = 0;  // fractional offsets
};

// False when the grid (with its bilinear neighbours) is not inside `img`, or x, y are not finite.
inline bool make_grid(const cv::Mat& img, double x, double y, int n, Grid* grid) {
  const double fx = std::floor(x), fy = std::floor(y);
  if (!(fx >= 0.0 && fy >= 0.0 && fx + n <= img.cols - 1 && fy + n <= img.rows - 1)) return false;
  grid->x0 = static_cast<int>(fx);
  grid->y0 = static_cast<int>(fy);
  grid->ax = static_cast<float>(x - fx);
  grid->ay = static_cast<float>(y - fy);
  return true;
}

// Samples the N x N grid, row-major, into `out`: a horizontal pass over N + 1 rows, then a
// vertical one, so each pixel is read and converted once.
template <int N>
inline void sample_grid(const cv::Mat& img, const Grid& g, float* out) {
  const size_t step = img.step[0];
  const uint8_t* row = img.ptr<uint8_t>(g.y0) + g.x0;
  float h[(N + 1) * N];
  for (int j = 0; j <= N; ++j, row += step) {
    float p[N + 1];
    for (int i = 0; i <= N; ++i) p[i] = row[i];
    for (int i = 0; i < N; ++i) h[j * N + i] = p[i] + g.ax * (p[i + 1] - p[i]);
  }
  for (int j = 0; j < N; ++j) {
    for (int i = 0; i < N; ++i) {
      out[j * N + i] = h[j * N + i] + g.ay * (h[(j + 1) * N + i] - h[j * N + i]);
    }
  }
}

// True when bilinear interpolation at (x, y) stays inside `img`.
inline bool bilinear_inside(const cv::Mat& img, double x, double y) {
  return x >= 0.0 && y >= 0.0 && x < img.cols - 1 && y < img.rows - 1;
}

// Bilinear interpolation; (x, y) must satisfy bilinear_inside.
inline float sample_bilinear(const cv::Mat& img, double x, double y) {
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const float ax = static_cast<float>(x - x0), ay = static_cast<float>(y - y0);
  const uint8_t* r0 = img.ptr<uint8_t>(y0) + x0;
  const uint8_t* r1 = r0 + img.step[0];
  return (1.f - ay) * ((1.f - ax) * r0[0] + ax * r0[1]) + ay * ((1.f - ax) * r1[0] + ax * r1[1]);
}

// Bilinear interpolation at (x, y) clamped into `img` (2x2 pixels or more): outside, the value
// at the nearest border. For coarse pyramid levels, where a patch near the border is still
// worth aligning.
inline float sample_bilinear_clamped(const cv::Mat& img, double x, double y) {
  return sample_bilinear(img, std::clamp(x, 0.0, img.cols - 1.0 - 1e-6),
                         std::clamp(y, 0.0, img.rows - 1.0 - 1e-6));
}

// As make_grid + sample_grid with sample_bilinear_clamped.
template <int N>
inline void sample_grid_clamped(const cv::Mat& img, double x, double y, float* out) {
  for (int j = 0; j < N; ++j) {
    for (int i = 0; i < N; ++i) *out++ = sample_bilinear_clamped(img, x + i, y + j);
  }
}

}  // namespace hs::direct
