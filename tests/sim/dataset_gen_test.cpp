// In-memory generation and the EuRoC writer: timing, events in the images, determinism, and
// output that is complete or absent.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <opencv2/core.hpp>
#include <sstream>

#include "common/calib/camera_calib.h"
#include "common/core/csv.h"
#include "common/core/error.h"
#include "common/sim/dataset_gen.h"
#include "common/sim/euroc_writer.h"
#include "scenario_test_util.h"

namespace hs::sim {
namespace {

namespace fs = std::filesystem;
using testing::sparse_scenario;
using testing::TempDir;
using testing::test_scenario;

size_t frame_at(const DatasetGenerator& gen, double t_rel_s) {
  const int64_t t = gen.scenario().start_time_ns + s_to_ns(t_rel_s);
  const auto& times = gen.frame_times_ns();
  return static_cast<size_t>(std::lower_bound(times.begin(), times.end(), t) - times.begin());
}

TEST(DatasetGenTest, SensorTimingAndGroundTruth) {
  Scenario sc = test_scenario("room_mav");
  sc.duration_s = 3.0;
  const DatasetGenerator gen(sc, {false});
  ASSERT_EQ(gen.num_frames(), 61u);
  for (size_t i = 0; i < gen.num_frames(); ++i)
    EXPECT_EQ(gen.frame_times_ns()[i], sc.start_time_ns + static_cast<int64_t>(i) * 50'000'000);
  ASSERT_EQ(gen.imu().samples.size(), 601u);
  ASSERT_EQ(gen.imu().truth.size(), 601u);
  for (size_t k = 0; k < gen.imu().truth.size(); ++k) {
    const NavState& s = gen.imu().truth[k];
    EXPECT_EQ(s.t_ns, gen.imu().samples[k].t_ns);
    EXPECT_EQ(s.t_ns, sc.start_time_ns + static_cast<int64_t>(k) * 5'000'000);
    EXPECT_LT((s.p_w_b - gen.body_at(s.t_ns).p_w_b).norm(), 1e-12);
  }
  EXPECT_EQ(gen.imu().truth.front().gyro_bias, sc.imu.gyro_bias);
}

uint64_t fnv1a(const void* data, size_t size, uint64_t h = 1469598103934665603ull) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < size; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

// Hash of everything a short in-memory run produces (checking the image format on the way).
uint64_t run_hash(uint64_t seed) {
  Scenario sc = sparse_scenario("room_mav");
  sc.duration_s = 0.1;
  sc.seed = seed;
  DatasetGenerator gen(sc);
  uint64_t h = 0;
  for (const ImuSample& s : gen.imu().samples) {
    h = fnv1a(s.gyro.data(), sizeof(double) * 3, h ^ static_cast<uint64_t>(s.t_ns));
    h = fnv1a(s.accel.data(), sizeof(double) * 3, h);
  }
  for (size_t i = 0; i < gen.num_frames(); ++i) {
    const SimStereoFrame f = gen.frame(i);
    EXPECT_EQ(f.t_ns, gen.frame_times_ns()[i]);
    for (const cv::Mat* im : {&f.cam0, &f.cam1}) {
      EXPECT_EQ(im->type(), CV_8UC1);
      EXPECT_EQ(im->cols, 752);
      EXPECT_EQ(im->rows, 480);
    }
    EXPECT_GT(cv::norm(f.cam0, f.cam1, cv::NORM_L1), 0.0) << "the cameras see different views";
    h = fnv1a(f.cam0.data, f.cam0.total(), h);
    h = fnv1a(f.cam1.data, f.cam1.total(), h);
  }
  return h;
}

TEST(DatasetGenTest, SameSeedSameDataOtherSeedOtherData) {
  const uint64_t h4 = run_hash(4);
  EXPECT_EQ(run_hash(4), h4);
  EXPECT_NE(run_hash(5), h4);
}

bool all_black(const cv::Mat& im) {
  return cv::countNonZero(im) == 0;
}

TEST(DatasetGenTest, BlackoutFramesAreBlackForTwoSeconds) {
  DatasetGenerator gen(test_scenario("blackout"));
  ASSERT_EQ(gen.scenario().events.blackouts.size(), 1u);
  const size_t first = frame_at(gen, 15.0), last = frame_at(gen, 17.0);
  EXPECT_EQ(gen.frame_times_ns()[last] - gen.frame_times_ns()[first], s_to_ns(2.0));
  for (const size_t i : {first, (first + last) / 2, last}) {
    const SimStereoFrame f = gen.frame(i);
    EXPECT_TRUE(f.blackout);
    EXPECT_TRUE(all_black(f.cam0) && all_black(f.cam1)) << i;
  }
  for (const size_t i : {first - 1, last + 1}) {
    const SimStereoFrame f = gen.frame(i);
    EXPECT_FALSE(f.blackout);
    EXPECT_FALSE(all_black(f.cam0) || all_black(f.cam1)) << i;
  }
}

TEST(DatasetGenTest, MissingBlackoutFramesLeaveATwoSecondHole) {
  Scenario sc = test_scenario("blackout");
  sc.events.blackout_mode = BlackoutMode::kMissing;
  const DatasetGenerator gen(sc, {false});
  const auto& t = gen.frame_times_ns();
  int holes = 0;
  for (size_t i = 1; i < t.size(); ++i) {
    if (t[i] - t[i - 1] == 50'000'000) continue;
    ++holes;
    EXPECT_EQ(t[i - 1] - sc.start_time_ns, s_to_ns(14.95));
    EXPECT_EQ(t[i] - sc.start_time_ns, s_to_ns(17.05));
  }
  EXPECT_EQ(holes, 1);
}

// Fraction of horizontally adjacent pixel pairs differing by more than sensor noise could.
double strong_edge_fraction(const cv::Mat& im) {
  cv::Mat a, b, diff;
  im.colRange(1, im.cols).convertTo(a, CV_16S);
  im.colRange(0, im.cols - 1).convertTo(b, CV_16S);
  cv::absdiff(a, b, diff);
  return static_cast<double>(cv::countNonZero(diff > 30)) / static_cast<double>(diff.total());
}

TEST(DatasetGenTest, TexturelessWindowShowsNoTexture) {
  DatasetGenerator gen(test_scenario("textureless"));
  ASSERT_EQ(gen.scenario().events.textureless.size(), 1u);
  const TimeWindow w = gen.scenario().events.textureless[0];
  for (int k = 0; k <= 4; ++k) {
    const double t = ns_to_s(w.start_ns + (w.end_ns - w.start_ns) * k / 4);
    const SimStereoFrame f = gen.frame(frame_at(gen, t));
    EXPECT_LT(strong_edge_fraction(f.cam0), 0.002) << t;
    EXPECT_LT(strong_edge_fraction(f.cam1), 0.002) << t;
  }
  for (const double t : {3.0, 30.0}) {
    const SimStereoFrame f = gen.frame(frame_at(gen, t));
    EXPECT_GT(strong_edge_fraction(f.cam0), 0.02) << t;
  }
}

TEST(DatasetGenTest, IlluminationStepsChangeBrightness) {
  Scenario sc = test_scenario("illumination_step");
  ASSERT_EQ(sc.events.gain_steps.size(), 2u);
  sc.camera.noise = false;
  DatasetGenerator gen(sc);
  const auto mean_at = [&](double t) { return cv::mean(gen.frame(frame_at(gen, t)).cam0)[0]; };
  const double up = mean_at(12.0) / mean_at(11.95);
  const double down = mean_at(24.0) / mean_at(23.95);
  EXPECT_NEAR(up, 1.4, 0.1);  // less than 1.4 where bright pixels saturate
  EXPECT_NEAR(down, 0.6 / 1.4, 0.05);
}

std::map<std::string, std::string> read_tree(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (!e.is_regular_file()) continue;
    std::ifstream in(e.path(), std::ios::binary);
    files[fs::relative(e.path(), root).string()] =
        std::string(std::istreambuf_iterator<char>(in), {});
  }
  return files;
}

TEST(EurocWriterTest, WritesEurocLayoutDeterministically) {
  TempDir dir("writer");
  Scenario sc = sparse_scenario("room_mav");
  sc.duration_s = 0.15;
  {
    DatasetGenerator gen(sc);  // rendering twice gives the same bytes
    write_euroc(gen, (dir.path() / "a").string());
    write_euroc(gen, (dir.path() / "b").string());
    Scenario other_seed = sc;
    other_seed.seed = sc.seed + 1;
    DatasetGenerator other(other_seed);
    write_euroc(other, (dir.path() / "c").string());
  }
  const auto a = read_tree(dir.path() / "a"), b = read_tree(dir.path() / "b"),
             c = read_tree(dir.path() / "c");
  EXPECT_EQ(a, b) << "same seed: byte-identical";
  ASSERT_EQ(a.size(), c.size());
  EXPECT_NE(a.at("mav0/imu0/data.csv"), c.at("mav0/imu0/data.csv"));
  EXPECT_NE(a.at("mav0/cam0/data/1700000000050000000.png"),
            c.at("mav0/cam0/data/1700000000050000000.png"));
  // Nothing but the three datasets in the parent directory: no temporaries left.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 3);

  const fs::path mav0 = dir.path() / "a" / "mav0";
  for (const char* f : {"body.yaml", "cam0/sensor.yaml", "cam1/sensor.yaml", "imu0/sensor.yaml"})
    EXPECT_TRUE(fs::exists(mav0 / f)) << f;
  const DatasetGenerator gen(sc, {false});
  for (const char* cam : {"cam0", "cam1"}) {
    CsvReader csv((mav0 / cam / "data.csv").string());
    CsvRow row;
    size_t rows = 0;
    while (csv.next(row)) {
      EXPECT_EQ(row.fields[1], std::to_string(gen.frame_times_ns()[rows]) + ".png");
      EXPECT_TRUE(fs::exists(mav0 / cam / "data" / row.fields[1]));
      ++rows;
    }
    EXPECT_EQ(rows, gen.num_frames());
  }
  const CameraCalib cam1 = read_camera_yaml((mav0 / "cam1" / "sensor.yaml").string());
  EXPECT_TRUE(cam1.T_b_c.isApprox(sc.camera.calib.cam1.T_b_c, 1e-12));

  CsvReader gt((mav0 / "state_groundtruth_estimate0" / "data.csv").string());
  CsvRow row;
  size_t k = 0;
  while (gt.next(row)) {
    ASSERT_EQ(row.fields.size(), 17u);
    const NavState& s = gen.imu().truth.at(k++);
    EXPECT_EQ(gt.int64_at(row, 0), s.t_ns);
    EXPECT_NEAR(gt.double_at(row, 1), s.p_w_b.x(), 1e-9);
    const Eigen::Quaterniond q(gt.double_at(row, 4), gt.double_at(row, 5), gt.double_at(row, 6),
                               gt.double_at(row, 7));
    EXPECT_LT(q.angularDistance(s.q_w_b), 1e-8);
    EXPECT_NEAR(gt.double_at(row, 8), s.v_w.x(), 1e-9);
    EXPECT_NEAR(gt.double_at(row, 11), s.gyro_bias.x(), 1e-12);
    EXPECT_NEAR(gt.double_at(row, 16), s.accel_bias.z(), 1e-12);
  }
  EXPECT_EQ(k, gen.imu().truth.size());
  CsvReader imu((mav0 / "imu0" / "data.csv").string());
  k = 0;
  while (imu.next(row)) {
    ASSERT_EQ(row.fields.size(), 7u);
    EXPECT_NEAR(imu.double_at(row, 4), gen.imu().samples.at(k++).accel.x(), 1e-8);
  }
  EXPECT_EQ(k, gen.imu().samples.size());
}

TEST(EurocWriterTest, RefusesToReplaceUnlessAskedAndNeverLeavesHalfAnOutput) {
  TempDir dir("writer_atomic");
  Scenario sc = sparse_scenario("room_mav");
  sc.duration_s = 0.15;
  const fs::path out = dir.path() / "out";
  fs::create_directories(out);
  std::ofstream(out / "old.txt") << "old";
  DatasetGenerator gen(sc);
  EXPECT_THROW(write_euroc(gen, out.string()), InputError);
  EXPECT_TRUE(fs::exists(out / "old.txt"));

  // A run that fails half way leaves the old output untouched and no temporaries.
  EurocWriteOptions failing;
  failing.overwrite = true;
  failing.progress = [](size_t done, size_t) {
    if (done == 2) throw std::runtime_error("interrupted");
  };
  EXPECT_THROW(write_euroc(gen, out.string(), failing), std::runtime_error);
  EXPECT_TRUE(fs::exists(out / "old.txt"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);

  EurocWriteOptions replace;
  replace.overwrite = true;
  write_euroc(gen, out.string(), replace);
  EXPECT_FALSE(fs::exists(out / "old.txt"));
  EXPECT_TRUE(fs::exists(out / "mav0" / "imu0" / "data.csv"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);
}

}  // namespace
}  // namespace hs::sim
