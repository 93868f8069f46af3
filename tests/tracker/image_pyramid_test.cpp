#include "tracker/image_pyramid.h"

#include <gtest/gtest.h>

namespace hs {
namespace {

TEST(ImagePyramid, HalvesAndAverages) {
  cv::Mat img(480, 752, CV_8UC1);
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x)
      img.at<uint8_t>(y, x) = static_cast<uint8_t>((x * 7 + y * 3) % 251);
  const ImagePyramid pyr = build_pyramid(img, 4);
  ASSERT_EQ(pyr.num_levels(), 4);
  EXPECT_EQ(pyr.levels[3].cols, 94);
  EXPECT_EQ(pyr.levels[3].rows, 60);
  const int sum = img.at<uint8_t>(10, 20) + img.at<uint8_t>(10, 21) + img.at<uint8_t>(11, 20) +
                  img.at<uint8_t>(11, 21);
  EXPECT_EQ(pyr.levels[1].at<uint8_t>(5, 10), (sum + 2) / 4);
  EXPECT_THROW(build_pyramid(cv::Mat(), 4), std::invalid_argument);
}

}  // namespace
}  // namespace hs
