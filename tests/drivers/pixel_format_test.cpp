#include "drivers/camera/pixel_format.h"

#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <stdexcept>
#include <vector>

namespace hs {
namespace {

TEST(PixelFormat, FourccsAndNames) {
  EXPECT_EQ(pixel_format_from_fourcc(V4L2_PIX_FMT_GREY), PixelFormat::kGrey);
  EXPECT_EQ(pixel_format_from_fourcc(V4L2_PIX_FMT_Y16), PixelFormat::kY16);
  EXPECT_EQ(pixel_format_from_fourcc(V4L2_PIX_FMT_YUYV), PixelFormat::kYuyv);
  EXPECT_EQ(fourcc_name(V4L2_PIX_FMT_YUYV), "YUYV");
  EXPECT_EQ(pixel_format_from_name("Y8"), PixelFormat::kGrey);
  EXPECT_EQ(fourcc_of(pixel_format_from_name("Y16")), static_cast<uint32_t>(V4L2_PIX_FMT_Y16));
  try {
    pixel_format_from_fourcc(V4L2_PIX_FMT_MJPEG);
    ADD_FAILURE();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'MJPG' not supported"), std::string::npos) << e.what();
  }
}

TEST(PixelFormat, ConvertsEachFormatToMono8WithPaddedRows) {
  const int w = 4, h = 2;
  // GREY with 2 bytes of padding per row.
  const std::vector<uint8_t> grey = {1, 2, 3, 4, 0, 0, 5, 6, 7, 8, 0, 0};
  cv::Mat g = to_mono8(PixelFormat::kGrey, grey.data(), grey.size(), w, h, 6);
  EXPECT_EQ(g.at<uint8_t>(1, 3), 8);
  // Y16 little-endian: the high byte is kept.
  std::vector<uint8_t> y16;
  for (int i = 0; i < w * h; ++i) {
    y16.push_back(0xFF);                          // low byte: dropped
    y16.push_back(static_cast<uint8_t>(10 * i));  // high byte
  }
  cv::Mat y = to_mono8(PixelFormat::kY16, y16.data(), y16.size(), w, h, 2 * w);
  EXPECT_EQ(y.at<uint8_t>(1, 2), 60);
  // YUYV: Y0 U Y1 V.
  std::vector<uint8_t> yuyv;
  for (int i = 0; i < w * h / 2; ++i)
    for (uint8_t b :
         {static_cast<uint8_t>(2 * i), uint8_t{128}, static_cast<uint8_t>(2 * i + 1), uint8_t{128}})
      yuyv.push_back(b);
  cv::Mat yu = to_mono8(PixelFormat::kYuyv, yuyv.data(), yuyv.size(), w, h, 2 * w);
  EXPECT_EQ(yu.at<uint8_t>(0, 0), 0);
  EXPECT_EQ(yu.at<uint8_t>(1, 3), 7);
}

TEST(PixelFormat, ShortBuffersAndBadGeometryAreErrorsNotReads) {
  const std::vector<uint8_t> data(10, 0);
  EXPECT_THROW(to_mono8(PixelFormat::kGrey, data.data(), data.size(), 4, 3, 4), std::runtime_error);
  EXPECT_THROW(to_mono8(PixelFormat::kY16, data.data(), data.size(), 4, 1, 4), std::runtime_error);
  EXPECT_THROW(to_mono8(PixelFormat::kGrey, data.data(), data.size(), 0, 1, 4), std::runtime_error);
}

}  // namespace
}  // namespace hs
