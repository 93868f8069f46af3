#include "common/calib/camera_calib.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "common/core/error.h"

namespace hs {
namespace {

namespace fs = std::filesystem;

const std::string kSharedCalib = HS_SOURCE_DIR "/../shared/data/euroc/calib";
const std::string kSampleMav0 = HS_SOURCE_DIR "/tests/data/euroc_v1_01_static_sample/mav0";

class TempDir {
 public:
  TempDir() : path_(fs::temp_directory_path() / ("hs_calib_test_" + std::to_string(::getpid()))) {
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

void expect_same(const CameraCalib& a, const CameraCalib& b, double tol) {
  const PinholeRadtan& k = a.intrinsics;
  const PinholeRadtan& l = b.intrinsics;
  EXPECT_NEAR(k.fx, l.fx, tol);
  EXPECT_NEAR(k.fy, l.fy, tol);
  EXPECT_NEAR(k.cx, l.cx, tol);
  EXPECT_NEAR(k.cy, l.cy, tol);
  EXPECT_NEAR(k.k1, l.k1, tol);
  EXPECT_NEAR(k.k2, l.k2, tol);
  EXPECT_NEAR(k.p1, l.p1, tol);
  EXPECT_NEAR(k.p2, l.p2, tol);
  EXPECT_EQ(k.width, l.width);
  EXPECT_EQ(k.height, l.height);
  EXPECT_LT((a.T_b_c.matrix() - b.T_b_c.matrix()).norm(), tol);
  EXPECT_NEAR(a.rate_hz, b.rate_hz, tol);
}

TEST(CameraCalib, ReadsEurocSensorYaml) {
  if (!fs::exists(kSharedCalib + "/cam0.yaml")) {
    GTEST_SKIP() << "shared EuRoC data not found at " << kSharedCalib;
  }
  const StereoCalib builtin = euroc_stereo_calib();
  expect_same(read_camera_yaml(kSharedCalib + "/cam0.yaml"), builtin.cam0, 1e-9);
  expect_same(read_camera_yaml(kSharedCalib + "/cam1.yaml"), builtin.cam1, 1e-9);
}

TEST(CameraCalib, ReadsTheRepositorySample) {
  const StereoCalib s = read_stereo_calib(kSampleMav0);
  expect_same(s.cam0, euroc_stereo_calib().cam0, 1e-9);
  expect_same(s.cam1, euroc_stereo_calib().cam1, 1e-9);
}

TEST(CameraCalib, EurocBaseline) {
  const StereoCalib s = euroc_stereo_calib();
  EXPECT_NEAR(s.baseline(), 0.110, 0.001);
  // cam1 is to the right of cam0: +x in cam0's frame.
  EXPECT_GT(s.T_c0_c1().translation().x(), 0.10);
}

TEST(CameraCalib, WriteReadRoundTripIsExact) {
  TempDir dir;
  CameraCalib c = euroc_stereo_calib().cam1;
  c.rate_hz = 30.0;
  c.intrinsics.width = 640;
  const std::string path = dir.file("sensor.yaml");
  write_camera_yaml(path, c, "simulated \"cam1\": test");
  std::ifstream in(path);
  std::string first;
  std::getline(in, first);
  EXPECT_EQ(first, "%YAML:1.0");
  expect_same(read_camera_yaml(path), c, 1e-15);
}

// Writes a valid file with `from` replaced by `to`, expects an InputError naming the file
// and line `line`, containing `what`.
void expect_error(const std::string& from, const std::string& to, int line,
                  const std::string& what) {
  TempDir dir;
  const std::string path = dir.file("bad.yaml");
  write_camera_yaml(path, euroc_stereo_calib().cam0, "bad");
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
  write_text(path, text);
  try {
    read_camera_yaml(path);
    FAIL() << "no error for " << to;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path + ":" + std::to_string(line) + ":"), std::string::npos) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  }
}

TEST(CameraCalib, BadFilesNameFileAndLine) {
  // Line numbers of write_camera_yaml's layout (the same as EuRoC's).
  expect_error("camera_model: pinhole", "camera_model: omni", 18, "camera_model");
  expect_error("distortion_model: radial-tangential", "distortion_model: equidistant", 20,
               "distortion_model");
  expect_error("resolution: [752, 480]", "resolution: [752]", 17, "resolution");
  expect_error("rate_hz: 20", "rate_hz: fast", 16, "rate_hz");
  expect_error("intrinsics: [", "intrinsics: [abc, ", 19, "intrinsics");
  expect_error("rate_hz: 20", "rate: 20", 3, "missing key 'rate_hz'");  // where the map starts
  expect_error("  data: [0.0148", "  data: [5.0148", 10, "rigid");
  expect_error("resolution: [752, 480]", "resolution: [752, 480", 18, "invalid YAML");
}

TEST(CameraCalib, MissingFileIsAnInputError) {
  EXPECT_THROW(read_camera_yaml("/nonexistent/sensor.yaml"), InputError);
}

}  // namespace
}  // namespace hs
