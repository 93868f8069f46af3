#include "common/lcm/dataset_log.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <opencv2/imgcodecs.hpp>

#include "common/lcm/decode.h"
#include "tests/dataset/dataset_test_util.h"

namespace hs {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

bool same_pixels(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && cv::norm(a, b, cv::NORM_INF) == 0.0;
}

// Reads a log written by write_dataset_log and checks it against the reader: every frame,
// IMU sample and ground-truth state exactly once, in order, with sensor-time event stamps, and
// all IMU samples up to a frame's time logged before that frame.
void expect_log_matches(const std::string& path, const EurocReader& r, const DatasetLogOptions& o) {
  lcm::LogFile log(path, "r");
  ASSERT_TRUE(log.good());
  std::vector<ImuSample> imu;
  size_t frames = 0, gt = 0;
  int64_t prev_stamp = INT64_MIN;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    EXPECT_GE(e->timestamp, prev_stamp);
    prev_stamp = e->timestamp;
    const size_t n = static_cast<size_t>(e->datalen);
    if (e->channel == o.channels.cam_stereo) {
      const StereoFrame f = frame_from_msg(
          decode_message<hsslam::stereo_frame_t>(e->data, n, e->channel), e->channel);
      ASSERT_LT(frames, r.frames().size());
      const StereoFrame expected = r.load_frame(frames++);
      EXPECT_EQ(e->timestamp, f.t_ns / 1000);
      EXPECT_EQ(f.seq, expected.seq);
      EXPECT_EQ(f.t_ns, expected.t_ns);
      EXPECT_TRUE(same_pixels(f.cam0, expected.cam0));
      EXPECT_TRUE(same_pixels(f.cam1, expected.cam1));
      const size_t due = static_cast<size_t>(std::count_if(
          r.imu().begin(), r.imu().end(), [&](const ImuSample& s) { return s.t_ns <= f.t_ns; }));
      EXPECT_EQ(imu.size(), due) << "IMU samples up to frame " << f.seq << " not all sent";
    } else if (e->channel == o.channels.imu) {
      const std::vector<ImuSample> batch =
          imu_batch_from_msg(decode_message<hsslam::imu_batch_t>(e->data, n, e->channel), "IMU");
      EXPECT_LE(batch.size(), static_cast<size_t>(o.imu_batch));
      EXPECT_EQ(e->timestamp, batch.back().t_ns / 1000);
      imu.insert(imu.end(), batch.begin(), batch.end());
    } else if (e->channel == o.channels.ground_truth) {
      const NavState x = ground_truth_from_msg(
          decode_message<hsslam::ground_truth_t>(e->data, n, e->channel), e->channel);
      ASSERT_LT(gt, r.ground_truth().size());
      EXPECT_EQ(x.t_ns, r.ground_truth()[gt].t_ns);
      EXPECT_EQ(x.p_w_b, r.ground_truth()[gt++].p_w_b);
      EXPECT_EQ(e->timestamp, x.t_ns / 1000);
    } else {
      ADD_FAILURE() << "unexpected channel " << e->channel;
    }
  }
  EXPECT_EQ(frames, r.frames().size());
  EXPECT_EQ(gt, r.ground_truth().size());
  ASSERT_EQ(imu.size(), r.imu().size());
  for (size_t i = 0; i < imu.size(); ++i) {
    EXPECT_EQ(imu[i].t_ns, r.imu()[i].t_ns);
    EXPECT_EQ(imu[i].accel, r.imu()[i].accel);
  }
}

// No file beside `path` other than `path` itself (no stray temp files).
std::vector<std::string> files_in(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename());
  return names;
}

TEST(DatasetLog, SampleMono8DefaultChannels) {
  test::TempDir dir;
  const EurocReader r(test::kSampleRoot);
  DatasetLogOptions o;
  std::vector<size_t> progress;
  const std::string path = dir.path() + "/sample.lcmlog";
  const DatasetLogSummary s =
      write_dataset_log(r, o, path, [&](size_t done, size_t) { progress.push_back(done); });
  EXPECT_EQ(s.frames, static_cast<int64_t>(r.frames().size()));
  EXPECT_EQ(s.imu_samples, static_cast<int64_t>(r.imu().size()));
  EXPECT_EQ(s.ground_truth, static_cast<int64_t>(r.ground_truth().size()));
  EXPECT_EQ(s.first_t_ns, r.imu().front().t_ns);
  EXPECT_FALSE(progress.empty());
  expect_log_matches(path, r, o);
  EXPECT_EQ(files_in(dir.path()), std::vector<std::string>{"sample.lcmlog"});
}

TEST(DatasetLog, PngRenamedChannelsSmallBatchesNoGroundTruth) {
  test::TempDir dir;
  EurocOptions ro;
  ro.use_ground_truth = false;
  const EurocReader r(test::kSampleRoot, ro);
  DatasetLogOptions o;
  o.encoding = ImageEncoding::kPng;
  o.imu_batch = 3;
  o.channels.cam_stereo = "RIG_A";
  o.channels.imu = "RIG_A_IMU";
  const std::string path = dir.path() + "/sample.lcmlog";
  const DatasetLogSummary s = write_dataset_log(r, o, path);
  EXPECT_EQ(s.ground_truth, 0);
  EXPECT_GE(s.imu_messages, static_cast<int64_t>(r.imu().size() / 3));
  expect_log_matches(path, r, o);
}

TEST(DatasetLog, BadImageLeavesNoOutput) {
  test::SampleCopy ds;
  const EurocReader r(ds.root());
  ASSERT_TRUE(cv::imwrite(r.frames()[4].cam1, cv::Mat(10, 10, CV_8UC1, cv::Scalar(0))));
  test::TempDir dir;
  const std::string e = test::input_error_of(
      [&] { write_dataset_log(r, DatasetLogOptions(), dir.path() + "/out.lcmlog"); });
  EXPECT_THAT(e, HasSubstr(ds.mav0() + "/cam1/data.csv:6: "));
  EXPECT_THAT(e, HasSubstr("is 10x10"));
  EXPECT_TRUE(files_in(dir.path()).empty());
}

TEST(DatasetLog, UnwritableOutputIsAnInputError) {
  const EurocReader r(test::kSampleRoot);
  EXPECT_THAT(test::input_error_of([&] {
                write_dataset_log(r, DatasetLogOptions(), "/nonexistent/dir/out.lcmlog");
              }),
              HasSubstr("/nonexistent/dir/out.lcmlog"));
}

}  // namespace
}  // namespace hs
