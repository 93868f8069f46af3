#include "common/eval/trajectory.h"

#include <gtest/gtest.h>

#include "common/calib/camera_calib.h"

#include <cstdio>
#include <filesystem>

#include "common/core/error.h"
#include "common/eval/extrinsics.h"
#include "eval_test_util.h"

namespace hs {
namespace {

using test::write_temp;

// Expects `fn` to throw InputError whose message contains `needle`.
template <typename Fn>
void expect_input_error(Fn fn, const std::string& needle) {
  try {
    fn();
    FAIL() << "expected InputError containing '" << needle << "'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(Trajectory, ReadsTumWithExactNanosecondStamps) {
  const std::string p = write_temp(
      "# t x y z qx qy qz qw\n"
      "1403715273.262142976 1 2 3 0 0 0 1\n"
      "1403715273.3\t4 5 6 0 0 0.7071067811865476 0.7071067811865476\n");
  const Trajectory t = load_trajectory(p);
  ASSERT_EQ(t.poses.size(), 2u);
  EXPECT_EQ(t.poses[0].t_ns, 1403715273262142976LL);
  EXPECT_EQ(t.poses[1].t_ns, 1403715273300000000LL);
  EXPECT_TRUE(t.poses[0].T_w_b.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
  // qz = qw = sqrt(1/2): 90 degrees about z maps x onto y.
  EXPECT_TRUE(
      (t.poses[1].T_w_b.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY()));
  std::remove(p.c_str());
}

TEST(Trajectory, ReadsEurocCsvWithExtraColumnsAndWxyzOrder) {
  const std::string p = write_temp(
      "#time(ns),px,py,pz,qw,qx,qy,qz,vx,vy,vz\n"
      "100,1,2,3,0.7071067811865476,0.7071067811865476,0,0,9,9,9\n"
      "200,4,5,6,1,0,0,0,9,9,9\n",
      ".csv");
  EXPECT_EQ(detect_trajectory_format(p), TrajectoryFormat::kEuroc);
  const Trajectory t = load_trajectory(p);
  ASSERT_EQ(t.poses.size(), 2u);
  EXPECT_EQ(t.poses[1].t_ns, 200);
  // qw = qx = sqrt(1/2): 90 degrees about x maps y onto z.
  EXPECT_TRUE(
      (t.poses[0].T_w_b.linear() * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitZ()));
  std::remove(p.c_str());
}

TEST(Trajectory, ReadsRealEurocGroundTruthSample) {
  const std::string p = HS_SOURCE_DIR
      "/tests/data/euroc_v1_01_static_sample/mav0/state_groundtruth_estimate0/data.csv";
  const Trajectory t = load_trajectory(p);
  ASSERT_EQ(t.poses.size(), 6u);
  EXPECT_EQ(t.poses[0].t_ns, 1403715273262142976LL);
  EXPECT_NEAR(t.poses[0].T_w_b.translation().x(), 0.878895, 1e-12);
}

TEST(Trajectory, SaveTumRoundTripsExactly) {
  const Trajectory in = test::figure_eight(20, 1403715273262142976LL);
  const std::string p = write_temp("");
  save_tum(p, in);
  const Trajectory out = load_trajectory(p, TrajectoryFormat::kTum);
  ASSERT_EQ(out.poses.size(), in.poses.size());
  for (size_t i = 0; i < in.poses.size(); ++i) {
    EXPECT_EQ(out.poses[i].t_ns, in.poses[i].t_ns);
    EXPECT_TRUE(out.poses[i].T_w_b.isApprox(in.poses[i].T_w_b, 1e-8));
  }
  std::remove(p.c_str());
}

TEST(Trajectory, MalformedLineNamesFileAndLine) {
  const std::string p = write_temp("# header\n1.0 0 0 0 0 0 0 1\n2.0 0 0 zero 0 0 0 1\n");
  expect_input_error([&] { load_trajectory(p); }, p + ":3:");
  std::remove(p.c_str());
}

TEST(Trajectory, MissingFieldNamesFileAndLine) {
  const std::string p = write_temp("1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 1\n");
  expect_input_error([&] { load_trajectory(p); }, p + ":2: TUM line needs 8 fields");
  std::remove(p.c_str());
}

TEST(Trajectory, DuplicateTimestampNamesFileAndLine) {
  const std::string p = write_temp("100,0,0,0,1,0,0,0\n200,0,0,0,1,0,0,0\n200,1,0,0,1,0,0,0\n");
  expect_input_error([&] { load_trajectory(p); }, p + ":3: duplicate timestamp");
  std::remove(p.c_str());
}

TEST(Trajectory, DecreasingTimestampNamesFileAndLine) {
  const std::string p = write_temp("2.0 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n");
  expect_input_error([&] { load_trajectory(p); }, p + ":2: timestamp decreases");
  std::remove(p.c_str());
}

TEST(Trajectory, OutOfRangeTimestampNamesFileAndLine) {
  const std::string tum = write_temp("1.0 0 0 0 0 0 0 1\n9999999999.5 0 0 0 0 0 0 1\n");
  expect_input_error([&] { load_trajectory(tum); }, tum + ":2: timestamp out of range");
  const std::string csv = write_temp("1,0,0,0,1,0,0,0\n9000000000000000000,0,0,0,1,0,0,0\n");
  expect_input_error([&] { load_trajectory(csv); }, csv + ":2: timestamp out of range");
  std::remove(tum.c_str());
  std::remove(csv.c_str());
}

TEST(Trajectory, NonUnitQuaternionIsRejectedSmallDeviationAccepted) {
  const std::string bad = write_temp("1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0.1 0.9\n");
  expect_input_error([&] { load_trajectory(bad); }, bad + ":2: quaternion is not unit");
  const std::string ok = write_temp("1.0 0 0 0 0 0 0 1.0004\n");
  EXPECT_NEAR(load_trajectory(ok).poses[0].T_w_b.linear().determinant(), 1.0, 1e-12);
  std::remove(bad.c_str());
  std::remove(ok.c_str());
}

TEST(Trajectory, EmptyFileNamesFile) {
  const std::string p = write_temp("# only a comment\n\n");
  expect_input_error([&] { load_trajectory(p); }, p + ": no poses");
  expect_input_error([&] { load_trajectory(p, TrajectoryFormat::kTum); }, p + ": no poses");
  std::remove(p.c_str());
}

TEST(Extrinsics, ReadsEurocSensorYaml) {
  const std::string p = write_temp("", ".yaml");
  CameraCalib calib = euroc_stereo_calib().cam0;
  calib.T_b_c.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  calib.T_b_c.translation() = Eigen::Vector3d(0.1, 0.2, 0.3);
  write_camera_yaml(p, calib);
  const Eigen::Isometry3d T_b_c = load_T_b_c_yaml(p);
  EXPECT_TRUE(T_b_c.translation().isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));
  EXPECT_TRUE((T_b_c.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY()));
  std::remove(p.c_str());
}

TEST(Extrinsics, ReadsRealCam0YamlWhenPresent) {
  const std::string p = HS_SOURCE_DIR "/../shared/data/euroc/calib/cam0.yaml";
  if (!std::filesystem::exists(p)) GTEST_SKIP() << "shared EuRoC data absent: " << p;
  const Eigen::Isometry3d T_b_c = load_T_b_c_yaml(p);
  EXPECT_NEAR(T_b_c.translation().x(), -0.0216401454975, 1e-12);
  EXPECT_NEAR(T_b_c.translation().y(), -0.064676986768, 1e-12);
}

TEST(Extrinsics, RejectsBadMatrices) {
  std::vector<std::string> args(16, "0");
  expect_input_error([&] { parse_T_b_c(args); }, "not orthonormal");
  args = {"1", "0", "0", "0", "0", "1", "0", "0", "0", "0", "1", "0", "0", "0", "0", "2"};
  expect_input_error([&] { parse_T_b_c(args); }, "last row");
  args[15] = "x";
  expect_input_error([&] { parse_T_b_c(args); }, "not a number");
  const std::string p = write_temp("%YAML:1.0\nT_BS:\n  data: [1, 0, 0]\n", ".yaml");
  expect_input_error([&] { load_T_b_c_yaml(p); }, p);
  std::remove(p.c_str());
  args = {"1", "0", "0", "0.5", "0", "1", "0", "-0.25", "0", "0", "1", "0", "0", "0", "0", "1"};
  EXPECT_TRUE(parse_T_b_c(args).translation().isApprox(Eigen::Vector3d(0.5, -0.25, 0)));
}

}  // namespace
}  // namespace hs
