#include "common/lcm/decode.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "common/lcm/convert.h"
#include "tests/dataset/dataset_test_util.h"
#include "tests/lcm/lcm_test_util.h"

namespace hs {
namespace {

using test::encode_bytes;
using test::input_error_of;
using ::testing::HasSubstr;

hsslam::stereo_frame_t small_frame_msg(ImageEncoding encoding) {
  StereoFrame f;
  f.t_ns = 123456789;
  f.seq = 3;
  f.cam0 = cv::Mat(4, 6, CV_8UC1);
  cv::randu(f.cam0, 0, 255);
  f.cam1 = 255 - f.cam0;
  return frame_to_msg(f, encoding);
}

TEST(Decode, ValidBytesRoundTrip) {
  const auto msg = small_frame_msg(ImageEncoding::kMono8);
  const std::vector<uint8_t> bytes = encode_bytes(msg);
  EXPECT_EQ(message_fingerprint(bytes.data(), bytes.size()), hsslam::stereo_frame_t::getHash());
  const auto back = decode_message<hsslam::stereo_frame_t>(bytes.data(), bytes.size(), "CAM");
  EXPECT_EQ(encode_bytes(back), bytes);
}

TEST(Decode, EveryTruncationIsAClearError) {
  const std::vector<uint8_t> bytes = encode_bytes(small_frame_msg(ImageEncoding::kMono8));
  for (size_t n = 0; n < bytes.size(); ++n) {
    const std::string e =
        input_error_of([&] { decode_message<hsslam::stereo_frame_t>(bytes.data(), n, "CAM"); });
    EXPECT_THAT(e, HasSubstr("CAM: ")) << n;
  }
}

TEST(Decode, WrongTypeAndTrailingBytes) {
  std::vector<uint8_t> imu = encode_bytes(imu_batch_to_msg({ImuSample{}}, 0));
  EXPECT_THAT(input_error_of(
                  [&] { decode_message<hsslam::stereo_frame_t>(imu.data(), imu.size(), "CAM"); }),
              HasSubstr("CAM: message is not a stereo_frame_t (fingerprint mismatch)"));
  imu.push_back(0);
  EXPECT_THAT(
      input_error_of([&] { decode_message<hsslam::imu_batch_t>(imu.data(), imu.size(), "IMU"); }),
      HasSubstr("IMU: imu_batch_t: 1 trailing bytes"));
}

TEST(Decode, NegativeArrayLengthIsAClearError) {
  std::vector<uint8_t> bytes = encode_bytes(small_frame_msg(ImageEncoding::kMono8));
  bytes[8 + 8 + 8] = 0xFF;  // num_images (int8 after hash, t_ns, seq) = -1
  EXPECT_THAT(input_error_of([&] {
                decode_message<hsslam::stereo_frame_t>(bytes.data(), bytes.size(), "CAM");
              }),
              HasSubstr("CAM: stereo_frame_t: corrupt array length"));
}

// Flipping any single bit pattern in a valid message must give a frame or a clear error, never a
// crash or a frame that breaks its own invariants. (XOR 0x01 and 0x80 keep array lengths small
// or negative, so no huge allocation is attempted.)
TEST(Decode, CorruptedBytesNeverCrash) {
  for (ImageEncoding enc : {ImageEncoding::kMono8, ImageEncoding::kPng}) {
    const std::vector<uint8_t> good = encode_bytes(small_frame_msg(enc));
    int accepted = 0, rejected = 0;
    for (size_t i = 0; i < good.size(); ++i) {
      for (uint8_t mask : {0x01, 0x80}) {
        std::vector<uint8_t> bytes = good;
        bytes[i] ^= mask;
        try {
          const StereoFrame f = frame_from_msg(
              decode_message<hsslam::stereo_frame_t>(bytes.data(), bytes.size(), "CAM"), "CAM");
          EXPECT_EQ(f.cam0.type(), CV_8UC1);
          EXPECT_EQ(f.cam1.size(), f.cam0.size());
          ++accepted;
        } catch (const InputError&) {
          ++rejected;
        }
      }
    }
    EXPECT_GT(accepted, 0);  // e.g. flipped pixel bits are still a valid frame
    EXPECT_GT(rejected, 0);
  }
}

}  // namespace
}  // namespace hs
