#include "tracker/image_pyramid.h"

#include <stdexcept>

namespace hs {

namespace {

// 2x2 box average: exact for the half-pixel-shift convention in the header, and cheaper than
// a Gaussian pyrDown (a 5x5 filter), which the alignment does not need.
cv::Mat halve(const cv::Mat& src) {
  const int w = src.cols / 2, h = src.rows / 2;
  cv::Mat dst(h, w, CV_8UC1);
  for (int y = 0; y < h; ++y) {
    const uint8_t* r0 = src.ptr<uint8_t>(2 * y);
    const uint8_t* r1 = src.ptr<uint8_t>(2 * y + 1);
    uint8_t* out = dst.ptr<uint8_t>(y);
    for (int x = 0; x < w; ++x) {
      out[x] =
          static_cast<uint8_t>((r0[2 * x] + r0[2 * x + 1] + r1[2 * x] + r1[2 * x + 1] + 2) >> 2);
    }
  }
  return dst;
}

}  // namespace

ImagePyramid build_pyramid(const cv::Mat& image, int num_levels) {
  if (image.type() != CV_8UC1 || image.empty() || num_levels < 1)
    throw std::invalid_argument("build_pyramid: need a non-empty CV_8UC1 image and >= 1 level");
  ImagePyramid pyr;
  pyr.levels.reserve(num_levels);
  pyr.levels.push_back(image);
  for (int k = 1; k < num_levels; ++k) pyr.levels.push_back(halve(pyr.levels.back()));
  return pyr;
}

}  // namespace hs
