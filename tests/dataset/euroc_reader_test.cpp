#include "common/dataset/euroc_reader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <set>

#include "common/core/csv.h"
#include "tests/dataset/dataset_test_util.h"

namespace hs {
namespace {

using test::kSampleRoot;
using test::kSharedEuroc;
using ::testing::HasSubstr;

// First-column timestamps of a EuRoC CSV, read independently of the reader.
std::vector<int64_t> timestamps_of(const std::string& csv) {
  std::vector<int64_t> t;
  for (const std::string& line : test::read_lines(csv))
    if (!line.empty() && line[0] != '#') t.push_back(std::stoll(line.substr(0, line.find(','))));
  return t;
}

// Checks a reader against its folder: frames are exactly the cam0/cam1 timestamps present in
// both lists (or all cam0 ones for mono), every other row is reported, counts match the CSVs.
void expect_consistent(const EurocReader& r, const std::string& mav0, bool stereo) {
  const std::vector<int64_t> t0 = timestamps_of(mav0 + "/cam0/data.csv");
  std::vector<int64_t> expected = t0;
  size_t unpaired = 0;
  if (stereo) {
    const std::vector<int64_t> t1 = timestamps_of(mav0 + "/cam1/data.csv");
    expected.clear();
    std::set_intersection(t0.begin(), t0.end(), t1.begin(), t1.end(), std::back_inserter(expected));
    unpaired = t0.size() + t1.size() - 2 * expected.size();
  }
  EXPECT_EQ(r.stereo(), stereo);
  ASSERT_EQ(r.frames().size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(r.frames()[i].t_ns, expected[i]);
    EXPECT_EQ(r.frames()[i].cam1.empty(), !stereo);
  }
  EXPECT_EQ(r.dropped().size(), unpaired);
  EXPECT_EQ(r.imu().size(), timestamps_of(mav0 + "/imu0/data.csv").size());
  EXPECT_EQ(r.ground_truth().size(),
            timestamps_of(mav0 + "/state_groundtruth_estimate0/data.csv").size());
  for (size_t i = 1; i < r.imu().size(); ++i) EXPECT_LT(r.imu()[i - 1].t_ns, r.imu()[i].t_ns);
}

TEST(EurocReader, BundledSample) {
  const EurocReader r(kSampleRoot);
  expect_consistent(r, kSampleRoot + "/mav0", true);
  EXPECT_TRUE(r.dropped().empty());
  EXPECT_TRUE(r.has_ground_truth_folder());

  // Values straight from the first rows of imu0 and ground truth data.csv.
  CsvReader imu(kSampleRoot + "/mav0/imu0/data.csv");
  CsvRow row;
  ASSERT_TRUE(imu.next(row));
  EXPECT_EQ(r.imu()[0].t_ns, imu.int64_at(row, 0));
  EXPECT_DOUBLE_EQ(r.imu()[0].gyro.z(), imu.double_at(row, 3));
  EXPECT_DOUBLE_EQ(r.imu()[0].accel.x(), imu.double_at(row, 4));
  CsvReader gt(kSampleRoot + "/mav0/state_groundtruth_estimate0/data.csv");
  ASSERT_TRUE(gt.next(row));
  const NavState& x = r.ground_truth()[0];
  EXPECT_DOUBLE_EQ(x.p_w_b.y(), gt.double_at(row, 2));
  EXPECT_NEAR(x.q_w_b.w(), gt.double_at(row, 4), 1e-5);
  EXPECT_NEAR(x.q_w_b.z(), gt.double_at(row, 7), 1e-5);
  EXPECT_DOUBLE_EQ(x.accel_bias.z(), gt.double_at(row, 16));
}

TEST(EurocReader, LoadsFramesAsMono8MatchingTheFiles) {
  const EurocReader r(kSampleRoot);
  const cv::Mat left = cv::imread(r.frames()[2].cam0, cv::IMREAD_GRAYSCALE);
  EXPECT_EQ(r.image_size(), left.size());
  const StereoFrame f = r.load_frame(2);
  EXPECT_EQ(f.seq, 2);
  EXPECT_EQ(f.t_ns, r.frames()[2].t_ns);
  ASSERT_TRUE(f.stereo());
  EXPECT_EQ(f.cam0.type(), CV_8UC1);
  EXPECT_EQ(f.cam1.size(), f.cam0.size());
  EXPECT_EQ(cv::norm(f.cam0, left, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(f.cam0, f.cam1, cv::NORM_L1), 0.0);  // left and right differ
  EXPECT_THROW(r.load_frame(r.frames().size()), std::out_of_range);
}

TEST(EurocReader, AcceptsMav0ItselfAndMonoOption) {
  EurocOptions mono;
  mono.use_cam1 = false;
  mono.use_ground_truth = false;
  const EurocReader r(kSampleRoot + "/mav0", mono);
  EXPECT_FALSE(r.stereo());
  EXPECT_TRUE(r.ground_truth().empty());
  EXPECT_EQ(r.frames().size(), timestamps_of(kSampleRoot + "/mav0/cam0/data.csv").size());
  EXPECT_TRUE(r.load_frame(0).cam1.empty());
}

TEST(EurocReader, SharedStaticStereo) {
  const std::string root = kSharedEuroc + "/V1_01_static_stereo";
  if (!std::filesystem::exists(root)) GTEST_SKIP() << root << " absent (shared EuRoC pieces)";
  const EurocReader r(root);
  expect_consistent(r, root + "/mav0", true);
  // Real cam1 lists rows whose images are not shipped; each one must be reported.
  EXPECT_FALSE(r.dropped().empty());
  for (const std::string& d : r.dropped()) {
    EXPECT_THAT(d, HasSubstr("cam1/data.csv:"));
    EXPECT_THAT(d, HasSubstr("has no cam0 image"));
  }
  EXPECT_EQ(r.image_size(), cv::Size(752, 480));
  const StereoFrame last = r.load_frame(r.frames().size() - 1);
  EXPECT_EQ(last.cam1.size(), r.image_size());
}

TEST(EurocReader, SharedFlightMono) {
  const std::string root = kSharedEuroc + "/V1_01_flight_cam0";
  if (!std::filesystem::exists(root)) GTEST_SKIP() << root << " absent (shared EuRoC pieces)";
  const EurocReader r(root);
  expect_consistent(r, root + "/mav0", false);
  EXPECT_TRUE(r.load_frame(0).cam1.empty());
}

}  // namespace
}  // namespace hs
