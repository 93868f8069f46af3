#include "logger/png_recode.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "common/lcm/convert.h"
#include "hsslam/odometry_t.hpp"
#include "tests/lcm/lcm_test_util.h"

namespace hs {
namespace {

TEST(PngRecode, StereoImagesBecomeLosslessPng) {
  StereoFrame f;
  f.t_ns = 123456789;
  f.seq = 17;
  f.cam0 = cv::Mat(48, 64, CV_8UC1);
  f.cam1 = cv::Mat(48, 64, CV_8UC1);
  cv::randu(f.cam0, 0, 255);
  f.cam1.setTo(90);
  hsslam::stereo_frame_t raw = frame_to_msg(f, ImageEncoding::kMono8);
  raw.images[0].exposure_ns = 5000;
  std::vector<uint8_t> bytes = test::encode_bytes(raw);
  const size_t raw_size = bytes.size();
  std::string error;
  ASSERT_TRUE(recode_stereo_png(&bytes, &error)) << error;
  EXPECT_LT(bytes.size(), raw_size);  // the flat right image compresses

  hsslam::stereo_frame_t png;
  ASSERT_GT(png.decode(bytes.data(), 0, static_cast<int>(bytes.size())), 0);
  EXPECT_EQ(png.images[0].encoding, hsslam::image_t::PNG);
  EXPECT_EQ(png.images[0].exposure_ns, 5000);
  const StereoFrame back = frame_from_msg(png, "test");
  EXPECT_EQ(back.t_ns, f.t_ns);
  EXPECT_EQ(back.seq, f.seq);
  EXPECT_EQ(cv::norm(back.cam0, f.cam0, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(back.cam1, f.cam1, cv::NORM_INF), 0.0);
}

TEST(PngRecode, OtherMessagesAreLeftAsReceived) {
  hsslam::odometry_t pose{};
  std::vector<uint8_t> bytes = test::encode_bytes(pose);
  const std::vector<uint8_t> before = bytes;
  std::string error;
  EXPECT_FALSE(recode_stereo_png(&bytes, &error));
  EXPECT_FALSE(error.empty());
  EXPECT_EQ(bytes, before);
}

}  // namespace
}  // namespace hs
