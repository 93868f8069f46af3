// Each defect in a EuRoC folder gives an InputError naming the file and line (or is dropped and
// reported, for unpaired camera rows).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "common/dataset/euroc_reader.h"
#include "tests/dataset/dataset_test_util.h"

namespace hs {
namespace {

namespace fs = std::filesystem;
using test::edit_line;
using test::input_error_of;
using test::SampleCopy;
using ::testing::HasSubstr;

std::string open_error(const std::string& path) {
  return input_error_of([&] { EurocReader r(path); });
}

// Line 1 of every sample CSV is the '#' header, so data row k is line k + 1.
constexpr size_t kRow3 = 4;

TEST(EurocBadInput, MissingFolders) {
  test::TempDir empty;
  EXPECT_THAT(open_error(empty.path() + "/nope"), HasSubstr("does not exist"));
  EXPECT_THAT(open_error(empty.path()), HasSubstr("neither mav0/ nor cam0/"));
  {
    SampleCopy ds;
    fs::remove_all(ds.mav0() + "/imu0");
    EXPECT_THAT(open_error(ds.root()), HasSubstr("imu0/ folder missing"));
  }
  {
    SampleCopy ds;
    fs::remove(ds.mav0() + "/cam0/data.csv");
    const std::string e = open_error(ds.root());
    EXPECT_THAT(e, HasSubstr(ds.mav0() + "/cam0/data.csv"));
    EXPECT_THAT(e, HasSubstr("cannot open"));
  }
}

TEST(EurocBadInput, MalformedRows) {
  struct Case {
    std::string file, text, message;
  };
  const std::vector<Case> cases = {
      {"imu0/data.csv", "1403715273272143104,0.1,0.2,0.3,9.8,0.1", "expected 7 comma-separated"},
      {"imu0/data.csv", "1403715273272143104,0.1,0.2,x,9.8,0.1,0.2", "not a finite number: 'x'"},
      {"imu0/data.csv", "14037152732721431x4,0.1,0.2,0.3,9.8,0.1,0.2", "not an integer"},
      {"cam0/data.csv", "1403715273362142976", "expected 2 comma-separated"},
      {"cam1/data.csv", "1403715273362142976,", "empty image file name"},
      {"state_groundtruth_estimate0/data.csv",
       "1403715273362142976,0.8,2.1,0.9,0.5,0.5,0.5,0.6,0,0,0,0,0,0,0,0,0", "not unit length"},
      {"state_groundtruth_estimate0/data.csv", "1403715273362142976,1,2", "expected 17"},
  };
  for (const Case& c : cases) {
    SampleCopy ds;
    const std::string path = ds.mav0() + "/" + c.file;
    edit_line(path, kRow3, c.text);
    const std::string e = open_error(ds.root());
    EXPECT_THAT(e, HasSubstr(path + ":" + std::to_string(kRow3) + ": ")) << c.file;
    EXPECT_THAT(e, HasSubstr(c.message));
  }
}

TEST(EurocBadInput, DuplicateAndDecreasingTimestamps) {
  for (const std::string file :
       {"cam0/data.csv", "imu0/data.csv", "state_groundtruth_estimate0/data.csv"}) {
    {
      SampleCopy ds;
      const std::string path = ds.mav0() + "/" + file;
      std::vector<std::string> lines = test::read_lines(path);
      lines[kRow3 - 1] = lines[kRow3 - 2];  // row 3 repeats row 2
      test::write_lines(path, lines);
      const std::string e = open_error(ds.root());
      EXPECT_THAT(e, HasSubstr(path + ":" + std::to_string(kRow3) + ": duplicate timestamp"));
      EXPECT_THAT(e, HasSubstr("at line " + std::to_string(kRow3 - 1)));
    }
    {
      SampleCopy ds;
      const std::string path = ds.mav0() + "/" + file;
      std::vector<std::string> lines = test::read_lines(path);
      std::swap(lines[kRow3 - 1], lines[kRow3]);  // rows 3 and 4 swapped
      test::write_lines(path, lines);
      EXPECT_THAT(open_error(ds.root()),
                  HasSubstr(path + ":" + std::to_string(kRow3 + 1) + ": decreasing timestamp"));
    }
  }
}

TEST(EurocBadInput, UnpairedFramesAreDroppedAndReported) {
  SampleCopy ds;
  const std::string cam1 = ds.mav0() + "/cam1/data.csv";
  const std::string removed = test::read_lines(cam1)[kRow3 - 1];
  edit_line(cam1, kRow3, "", true);
  const EurocReader r(ds.root());
  EXPECT_EQ(r.frames().size(), 5u);
  ASSERT_EQ(r.dropped().size(), 1u);
  const std::string t = removed.substr(0, removed.find(','));
  EXPECT_THAT(r.dropped()[0], HasSubstr(ds.mav0() + "/cam0/data.csv:" + std::to_string(kRow3)));
  EXPECT_THAT(r.dropped()[0], HasSubstr("frame " + t + " has no cam1 image"));
  for (const FrameFiles& f : r.frames()) EXPECT_NE(std::to_string(f.t_ns), t);
}

TEST(EurocBadInput, NoPairsAtAll) {
  SampleCopy ds;
  const std::string cam1 = ds.mav0() + "/cam1/data.csv";
  test::write_lines(cam1, {"#timestamp [ns],filename", "1,1.png"});
  EXPECT_THAT(open_error(ds.root()), HasSubstr("no cam0/cam1 pairs"));
}

TEST(EurocBadInput, EmptyImu) {
  SampleCopy ds;
  test::write_lines(ds.mav0() + "/imu0/data.csv", {"#timestamp"});
  EXPECT_THAT(open_error(ds.root()), HasSubstr("no IMU samples"));
}

TEST(EurocBadInput, ListedImageMissing) {
  SampleCopy ds;
  const EurocReader good(ds.root());
  fs::remove(good.frames()[2].cam1);
  const std::string e = open_error(ds.root());
  EXPECT_THAT(e, HasSubstr(ds.mav0() + "/cam1/data.csv:" + std::to_string(kRow3) + ": "));
  EXPECT_THAT(e, HasSubstr("listed but missing"));
}

TEST(EurocBadInput, BadImagesFailWhenLoaded) {
  struct Case {
    cv::Mat image;  // empty: write garbage bytes instead
    std::string message;
  };
  const std::vector<Case> cases = {
      {cv::Mat(), "cannot read or decode"},
      {cv::Mat(480, 640, CV_8UC1, cv::Scalar(7)),
       "is 640x480, but the first cam0 image is 752x480"},
      {cv::Mat(480, 752, CV_8UC3, cv::Scalar(1, 2, 3)), "not 8-bit mono"},
      {cv::Mat(480, 752, CV_16UC1, cv::Scalar(300)), "not 8-bit mono"},
  };
  for (const Case& c : cases) {
    SampleCopy ds;
    const EurocReader r(ds.root());  // opening is cheap: images are only checked on load
    const std::string image = r.frames()[2].cam0;
    if (c.image.empty())
      test::write_lines(image, {"not a png"});
    else
      ASSERT_TRUE(cv::imwrite(image, c.image));
    EXPECT_NO_THROW(r.load_frame(1));
    const std::string e = input_error_of([&] { r.load_frame(2); });
    EXPECT_THAT(e, HasSubstr(ds.mav0() + "/cam0/data.csv:" + std::to_string(kRow3) + ": "));
    EXPECT_THAT(e, HasSubstr(image));
    EXPECT_THAT(e, HasSubstr(c.message));
  }
}

TEST(EurocBadInput, GroundTruthIsOptional) {
  SampleCopy ds;
  fs::remove_all(ds.mav0() + "/state_groundtruth_estimate0");
  const EurocReader r(ds.root());
  EXPECT_FALSE(r.has_ground_truth_folder());
  EXPECT_TRUE(r.ground_truth().empty());
}

}  // namespace
}  // namespace hs
