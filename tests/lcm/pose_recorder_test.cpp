#include "common/lcm/pose_recorder.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>

#include "common/core/csv.h"
#include "common/lcm/convert.h"
#include "tests/dataset/dataset_test_util.h"
#include "tests/lcm/lcm_test_util.h"

namespace hs {
namespace {

using test::encode_bytes;
using ::testing::HasSubstr;

NavState state_at(int64_t t_ns, double x) {
  NavState s;
  s.t_ns = t_ns;
  s.p_w_b = Eigen::Vector3d(x, -2.0 * x, 0.5);
  s.q_w_b = Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * x, Eigen::Vector3d::UnitZ()));
  return s;
}

template <class Msg>
void feed(PoseRecorder& rec, const std::string& channel, const Msg& msg) {
  const std::vector<uint8_t> bytes = encode_bytes(msg);
  rec.handle(channel, bytes.data(), bytes.size());
}

// Parses a TUM file back (independently of the writer's formatting code).
std::vector<std::vector<double>> read_tum(const std::string& path) {
  CsvReader csv(path, " ");
  std::vector<std::vector<double>> rows;
  CsvRow row;
  while (csv.next(row)) {
    std::vector<double> v;
    for (size_t i = 0; i < row.fields.size(); ++i) v.push_back(csv.double_at(row, i));
    rows.push_back(v);
  }
  return rows;
}

TEST(PoseRecorder, OdometryToTumSortedWithExactTimes) {
  PoseRecorder rec("POSE");
  const int64_t t0 = 1403715273262142976;
  feed(rec, "POSE", odometry_to_msg(state_at(t0 + 50000000, 2.0), 1, 0, 1, 1.0f));
  feed(rec, "POSE", odometry_to_msg(state_at(t0, 1.0), 0, 0, 1, 1.0f));  // late arrival
  feed(rec, "IMU", imu_batch_to_msg({ImuSample{}}, 0));
  feed(rec, "IMU", imu_batch_to_msg({ImuSample{}}, 1));
  EXPECT_EQ(rec.poses().size(), 2u);
  EXPECT_EQ(rec.type_name(), "odometry_t");
  EXPECT_EQ(rec.counts().at("POSE"), 2);
  EXPECT_EQ(rec.counts().at("IMU"), 2);
  EXPECT_EQ(rec.rejected(), 0);

  test::TempDir dir;
  const std::string path = dir.path() + "/est.tum";
  EXPECT_EQ(rec.write_tum(path), 1u);
  const std::vector<std::string> lines = test::read_lines(path);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].substr(0, lines[0].find(' ')), "1403715273.262142976");
  const auto rows = read_tum(path);
  const NavState first = state_at(t0, 1.0);
  ASSERT_EQ(rows[0].size(), 8u);
  EXPECT_NEAR(rows[0][1], first.p_w_b.x(), 1e-9);
  EXPECT_NEAR(rows[0][2], first.p_w_b.y(), 1e-9);
  EXPECT_NEAR(rows[0][6], first.q_w_b.z(), 1e-9);  // qx qy qz qw order
  EXPECT_NEAR(rows[0][7], first.q_w_b.w(), 1e-9);
  EXPECT_NEAR(rows[1][1], 2.0, 1e-9);
}

TEST(PoseRecorder, GroundTruthAndRejections) {
  PoseRecorder rec("GROUND_TRUTH");
  feed(rec, "GROUND_TRUTH", ground_truth_to_msg(state_at(100, 1.0)));
  const std::vector<uint8_t> junk = {1, 2, 3};
  rec.handle("GROUND_TRUTH", junk.data(), junk.size());
  feed(rec, "GROUND_TRUTH", imu_batch_to_msg({ImuSample{}}, 0));
  feed(rec, "GROUND_TRUTH", odometry_to_msg(state_at(200, 1.0), 0, 0, 1, 1.0f));  // mixed
  EXPECT_EQ(rec.poses().size(), 1u);
  EXPECT_EQ(rec.type_name(), "ground_truth_t");
  EXPECT_EQ(rec.rejected(), 3);
  EXPECT_THAT(rec.first_error(), HasSubstr("GROUND_TRUTH: "));
  EXPECT_EQ(rec.counts().at("GROUND_TRUTH"), 4);
}

// The real LCM path (in-process memq) delivers bytes that the recorder decodes.
void forward(const lcm::ReceiveBuffer* rbuf, const std::string& channel, PoseRecorder* rec) {
  rec->handle(channel, rbuf->data, rbuf->data_size);
}

TEST(PoseRecorder, ThroughMemqLcm) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  PoseRecorder rec("POSE");
  lcm.subscribeFunction(".*", &forward, &rec);
  for (int i = 0; i < 5; ++i) {
    const hsslam::odometry_t msg = odometry_to_msg(state_at(1000 + i, i), i, 0, 1, 0.5f);
    lcm.publish("POSE", &msg);
    EXPECT_EQ(lcm.handleTimeout(1000), 1);
  }
  ASSERT_EQ(rec.poses().size(), 5u);
  EXPECT_EQ(rec.poses()[4].t_ns, 1004);
  EXPECT_NEAR(rec.poses()[3].p_w_b.x(), 3.0, 0);
}

}  // namespace
}  // namespace hs
