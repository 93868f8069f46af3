#include "common/lcm/convert.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <opencv2/imgcodecs.hpp>

#include "common/dataset/euroc_reader.h"
#include "tests/dataset/dataset_test_util.h"

namespace hs {
namespace {

using test::input_error_of;
using ::testing::HasSubstr;

StereoFrame sample_frame() {
  return EurocReader(test::kSampleRoot).load_frame(1);
}

bool same_pixels(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0.0;
}

std::string frame_error(const hsslam::stereo_frame_t& msg) {
  return input_error_of([&] { frame_from_msg(msg, "CAM_STEREO"); });
}

TEST(ConvertFrame, Mono8AndPngRoundTripsAreExact) {
  const StereoFrame f = sample_frame();
  for (ImageEncoding enc : {ImageEncoding::kMono8, ImageEncoding::kPng}) {
    const hsslam::stereo_frame_t msg = frame_to_msg(f, enc);
    ASSERT_EQ(msg.num_images, 2);
    EXPECT_EQ(msg.images[0].width, f.cam0.cols);
    EXPECT_EQ(msg.images[0].size, static_cast<int32_t>(msg.images[0].data.size()));
    if (enc == ImageEncoding::kPng) {
      EXPECT_EQ(msg.images[0].stride, 0);
      EXPECT_LT(msg.images[0].data.size(), f.cam0.total());  // compressed
    } else {
      EXPECT_EQ(msg.images[0].stride, f.cam0.cols);
    }
    const StereoFrame back = frame_from_msg(msg, "CAM_STEREO");
    EXPECT_EQ(back.t_ns, f.t_ns);
    EXPECT_EQ(back.seq, f.seq);
    EXPECT_TRUE(same_pixels(back.cam0, f.cam0));
    EXPECT_TRUE(same_pixels(back.cam1, f.cam1));
  }
}

TEST(ConvertFrame, MonoRig) {
  StereoFrame f = sample_frame();
  f.cam1 = cv::Mat();
  const hsslam::stereo_frame_t msg = frame_to_msg(f, ImageEncoding::kMono8);
  EXPECT_EQ(msg.num_images, 1);
  const StereoFrame back = frame_from_msg(msg, "CAM");
  EXPECT_FALSE(back.stereo());
  EXPECT_TRUE(same_pixels(back.cam0, f.cam0));
}

TEST(ConvertFrame, PaddedRowsInAndOut) {
  // A region of interest has row step > width on the way in...
  const StereoFrame full = sample_frame();
  StereoFrame roi;
  roi.cam0 = full.cam0(cv::Rect(10, 20, 101, 37));
  ASSERT_FALSE(roi.cam0.isContinuous());
  const hsslam::stereo_frame_t msg = frame_to_msg(roi, ImageEncoding::kMono8);
  EXPECT_EQ(msg.images[0].stride, 101);
  EXPECT_TRUE(same_pixels(frame_from_msg(msg, "CAM").cam0, roi.cam0));

  // ...and a sender may pad its rows (stride > width) on the wire.
  hsslam::stereo_frame_t padded = msg;
  hsslam::image_t& im = padded.images[0];
  const int stride = 128;
  std::vector<uint8_t> data(static_cast<size_t>(stride) * im.height, 0xEE);
  for (int r = 0; r < im.height; ++r)
    std::copy_n(msg.images[0].data.begin() + r * im.width, im.width, data.begin() + r * stride);
  im.stride = stride;
  im.data = data;
  im.size = static_cast<int32_t>(data.size());
  EXPECT_TRUE(same_pixels(frame_from_msg(padded, "CAM").cam0, roi.cam0));
}

TEST(ConvertFrame, MalformedImagesAreRejected) {
  StereoFrame small;
  small.t_ns = 5;
  small.cam0 = cv::Mat(4, 6, CV_8UC1, cv::Scalar(9));
  small.cam1 = small.cam0.clone();
  const hsslam::stereo_frame_t good = frame_to_msg(small, ImageEncoding::kMono8);

  auto bad = good;
  bad.images[1].stride = 5;
  EXPECT_THAT(frame_error(bad), HasSubstr("CAM_STEREO: image 1: stride 5 < width 6"));

  bad = good;
  bad.images[0].data.pop_back();
  EXPECT_THAT(frame_error(bad), HasSubstr("size field 24 but 23 data bytes"));

  bad = good;
  bad.images[0].stride = 7;  // data and size unchanged: 24 != 7 * 4
  EXPECT_THAT(frame_error(bad), HasSubstr("expected stride*height = 28"));

  bad = good;
  bad.images[0].height = -4;
  EXPECT_THAT(frame_error(bad), HasSubstr("invalid size 6x-4"));

  bad = good;
  bad.images[0].encoding = 7;
  EXPECT_THAT(frame_error(bad), HasSubstr("unknown encoding 7"));

  bad = good;
  bad.num_images = 3;
  bad.images.push_back(bad.images[0]);
  EXPECT_THAT(frame_error(bad), HasSubstr("expected 1 or 2"));

  bad = good;
  bad.num_images = 0;
  bad.images.clear();
  EXPECT_THAT(frame_error(bad), HasSubstr("expected 1 or 2"));

  StereoFrame uneven = small;
  uneven.cam1 = cv::Mat(5, 6, CV_8UC1, cv::Scalar(1));
  EXPECT_THAT(frame_error(frame_to_msg(uneven, ImageEncoding::kMono8)),
              HasSubstr("differ in size"));
}

TEST(ConvertFrame, MalformedPngIsRejected) {
  StereoFrame small;
  small.cam0 = cv::Mat(4, 6, CV_8UC1, cv::Scalar(9));
  const hsslam::stereo_frame_t good = frame_to_msg(small, ImageEncoding::kPng);

  auto bad = good;
  bad.images[0].width = 8;  // PNG holds 6x4
  EXPECT_THAT(frame_error(bad), HasSubstr("PNG decodes to 6x4, declared 8x4"));

  bad = good;
  bad.images[0].data.resize(10);
  bad.images[0].size = 10;
  EXPECT_THAT(frame_error(bad), HasSubstr("PNG data does not decode"));

  bad = good;
  bad.images[0].stride = 6;
  EXPECT_THAT(frame_error(bad), HasSubstr("must be 0"));

  bad = good;
  ASSERT_TRUE(
      cv::imencode(".png", cv::Mat(4, 6, CV_8UC3, cv::Scalar(1, 2, 3)), bad.images[0].data));
  bad.images[0].size = static_cast<int32_t>(bad.images[0].data.size());
  EXPECT_THAT(frame_error(bad), HasSubstr("not 8-bit mono"));
}

std::vector<ImuSample> some_imu() {
  std::vector<ImuSample> s(3);
  for (int i = 0; i < 3; ++i) {
    s[i].t_ns = 1000 + 5 * i;
    s[i].gyro = Eigen::Vector3d(0.1 * i, -0.2, 0.3);
    s[i].accel = Eigen::Vector3d(9.8, 0.01 * i, -0.5);
  }
  return s;
}

TEST(ConvertImu, RoundTripAndChecks) {
  const std::vector<ImuSample> s = some_imu();
  const hsslam::imu_batch_t msg = imu_batch_to_msg(s, 42);
  EXPECT_EQ(msg.seq, 42);
  EXPECT_EQ(msg.t_ns, s.back().t_ns);
  const std::vector<ImuSample> back = imu_batch_from_msg(msg, "IMU");
  ASSERT_EQ(back.size(), s.size());
  for (size_t i = 0; i < s.size(); ++i) {
    EXPECT_EQ(back[i].t_ns, s[i].t_ns);
    EXPECT_EQ(back[i].gyro, s[i].gyro);
    EXPECT_EQ(back[i].accel, s[i].accel);
  }
  EXPECT_THROW(imu_batch_to_msg({}, 0), std::invalid_argument);

  const auto error = [](const hsslam::imu_batch_t& m) {
    return input_error_of([&] { imu_batch_from_msg(m, "IMU"); });
  };
  auto bad = msg;
  bad.samples[1].accel[2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT(error(bad), HasSubstr("IMU: sample 1 accel[2] is not finite"));
  bad = msg;
  bad.samples[2].t_ns = bad.samples[1].t_ns;
  EXPECT_THAT(error(bad), HasSubstr("sample 2: time"));
  bad = msg;
  bad.t_ns += 1;
  EXPECT_THAT(error(bad), HasSubstr("differs from the last sample"));
  bad = msg;
  bad.num_samples = 0;
  bad.samples.clear();
  EXPECT_THAT(error(bad), HasSubstr("num_samples 0"));
}

NavState some_state() {
  NavState x;
  x.t_ns = 1403715273262142976;
  x.p_w_b = Eigen::Vector3d(0.87, 2.18, 0.94);
  x.q_w_b = Eigen::Quaterniond(0.069, -0.824, -0.107, -0.552).normalized();
  x.v_w = Eigen::Vector3d(0.001, 0.002, -0.003);
  x.gyro_bias = Eigen::Vector3d(-0.002, 0.02, 0.07);
  x.accel_bias = Eigen::Vector3d(-0.018, 0.066, 0.031);
  return x;
}

void expect_same_state(const NavState& a, const NavState& b) {
  EXPECT_EQ(a.t_ns, b.t_ns);
  EXPECT_EQ(a.p_w_b, b.p_w_b);
  EXPECT_NEAR(a.q_w_b.angularDistance(b.q_w_b), 0.0, 1e-12);
  EXPECT_EQ(a.v_w, b.v_w);
  EXPECT_EQ(a.gyro_bias, b.gyro_bias);
  EXPECT_EQ(a.accel_bias, b.accel_bias);
}

TEST(ConvertGroundTruth, RoundTripAndChecks) {
  const NavState x = some_state();
  const hsslam::ground_truth_t msg = ground_truth_to_msg(x);
  EXPECT_DOUBLE_EQ(msg.q_w_b[0], x.q_w_b.w());  // (w, x, y, z) on the wire
  EXPECT_DOUBLE_EQ(msg.q_w_b[3], x.q_w_b.z());
  expect_same_state(ground_truth_from_msg(msg, "GT"), x);

  auto bad = msg;
  bad.q_w_b[0] += 0.1;
  EXPECT_THAT(input_error_of([&] { ground_truth_from_msg(bad, "GT"); }),
              HasSubstr("GT: q_w_b is not a unit quaternion"));
  bad = msg;
  bad.v_w[1] = INFINITY;
  EXPECT_THAT(input_error_of([&] { ground_truth_from_msg(bad, "GT"); }),
              HasSubstr("v_w[1] is not finite"));
}

TEST(ConvertOdometry, RoundTripAndChecks) {
  const NavState x = some_state();
  const hsslam::odometry_t msg = odometry_to_msg(x, 7, 2, hsslam::odometry_t::TRACKING, 0.75f);
  EXPECT_EQ(msg.seq, 7);
  EXPECT_EQ(msg.map_id, 2);
  EXPECT_EQ(msg.covariance[35], 0.0);
  expect_same_state(odometry_from_msg(msg, "POSE"), x);

  const auto error = [](const hsslam::odometry_t& m) {
    return input_error_of([&] { odometry_from_msg(m, "POSE"); });
  };
  auto bad = msg;
  bad.state = 9;
  EXPECT_THAT(error(bad), HasSubstr("unknown state 9"));
  bad = msg;
  bad.quality = 1.5f;
  EXPECT_THAT(error(bad), HasSubstr("outside [0, 1]"));
  bad = msg;
  bad.covariance[4] = NAN;
  EXPECT_THAT(error(bad), HasSubstr("covariance[4] is not finite"));
  bad = msg;
  bad.p_w_b[0] = NAN;
  EXPECT_THAT(error(bad), HasSubstr("p_w_b[0] is not finite"));
}

TEST(ConvertMapUpdate, RoundTripAndChecks) {
  MapCorrection c;
  c.seq = 4;
  c.map_id = 1;
  c.t_ns = 123;
  c.keyframes = {{7, some_state()}, {9, some_state()}};
  c.points = {{3, Eigen::Vector3d(1, 2, 3)}, {5, Eigen::Vector3d(-1, 0, 2)}};
  c.removed_points = {11};
  c.g_w = Eigen::Vector3d(0.05, -0.02, -9.8);
  const hsslam::map_update_t msg = map_update_to_msg(c);
  EXPECT_EQ(msg.kind, hsslam::map_update_t::LOCAL_BA);
  EXPECT_EQ(msg.previous_map_id, 1);
  EXPECT_EQ(msg.q_new_old[0], 1.0);  // no rigid correction
  const MapCorrection back = map_correction_from_msg(msg, "MAP_UPDATE");
  EXPECT_EQ(back.seq, 4);
  EXPECT_EQ(back.map_id, 1);
  EXPECT_EQ(back.t_ns, 123);
  ASSERT_EQ(back.keyframes.size(), 2u);
  EXPECT_EQ(back.keyframes[1].id, 9);
  expect_same_state(back.keyframes[1].state, c.keyframes[1].state);
  ASSERT_EQ(back.points.size(), 2u);
  EXPECT_EQ(back.points[1].p_w, c.points[1].p_w);
  EXPECT_EQ(back.removed_points, c.removed_points);
  EXPECT_EQ(back.g_w, c.g_w);

  const auto error = [](const hsslam::map_update_t& m) {
    return input_error_of([&] { map_correction_from_msg(m, "MAP_UPDATE"); });
  };
  auto bad = msg;
  bad.kind = hsslam::map_update_t::LOOP;
  EXPECT_THAT(error(bad), HasSubstr("kind LOOP is not supported"));
  bad = msg;
  bad.num_points = 3;
  EXPECT_THAT(error(bad), HasSubstr("num_points 3 but 2 entries"));
  bad = msg;
  bad.points[0].p_w[2] = NAN;
  EXPECT_THAT(error(bad), HasSubstr("point 3 p_w[2] is not finite"));
  bad = msg;
  bad.keyframes[1].id = 7;
  EXPECT_THAT(error(bad), HasSubstr("keyframe id 7 twice"));
  bad = msg;
  bad.keyframes[0].q_w_b[1] = 0.5;
  EXPECT_THAT(error(bad), HasSubstr("MAP_UPDATE: map_update_t seq 4: keyframe"));
  bad = msg;
  bad.removed_point_ids[0] = -2;
  EXPECT_THAT(error(bad), HasSubstr("removed point id -2 negative"));
  bad = msg;
  bad.g_w[0] = INFINITY;
  EXPECT_THAT(error(bad), HasSubstr("g_w[0] is not finite"));
}

TEST(ConvertRelocAnswer, RoundTripAndChecks) {
  RelocAnswer a;
  a.seq = 3;
  a.t_ns = 456;
  a.found = true;
  a.map_id = 5;
  a.keyframe_id = 42;
  a.T_w_b = some_state().T_w_b();
  a.inliers = 61;
  a.message = "found";
  const hsslam::reloc_answer_t msg = reloc_answer_to_msg(a);
  const RelocAnswer back = reloc_answer_from_msg(msg, "RELOC_ANSWER");
  EXPECT_EQ(back.seq, 3);
  EXPECT_EQ(back.t_ns, 456);
  EXPECT_TRUE(back.found);
  EXPECT_EQ(back.map_id, 5);
  EXPECT_EQ(back.keyframe_id, 42);
  EXPECT_EQ(back.inliers, 61);
  EXPECT_TRUE(back.T_w_b.isApprox(a.T_w_b, 1e-12));
  EXPECT_EQ(back.message, "found");

  const auto error = [](const hsslam::reloc_answer_t& m) {
    return input_error_of([&] { reloc_answer_from_msg(m, "RELOC_ANSWER"); });
  };
  hsslam::reloc_answer_t bad = msg;
  bad.pose.q_w_b[1] = 0.5;
  EXPECT_THAT(error(bad), HasSubstr("RELOC_ANSWER: reloc_answer_t seq 3: pose"));
  bad = msg;
  bad.pose.p_w_b[0] = NAN;
  EXPECT_THAT(error(bad), HasSubstr("p_w_b[0] is not finite"));
  bad = msg;
  bad.map_id = -1;
  EXPECT_THAT(error(bad), HasSubstr("map id -1"));
  // Not found: nothing else is read (a mapper without an atlas may leave the pose zero).
  bad.found = false;
  bad.pose.q_w_b[0] = 0.0;
  EXPECT_FALSE(reloc_answer_from_msg(bad, "RELOC_ANSWER").found);
}

TEST(ConvertEncoding, Names) {
  EXPECT_EQ(parse_image_encoding("png"), ImageEncoding::kPng);
  EXPECT_EQ(parse_image_encoding("mono8"), ImageEncoding::kMono8);
  EXPECT_THAT(input_error_of([] { parse_image_encoding("jpeg"); }), HasSubstr("'jpeg'"));
}

}  // namespace
}  // namespace hs
