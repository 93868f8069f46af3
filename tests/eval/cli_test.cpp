// End to end: runs the built hs-eval binary on real EuRoC ground truth.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/eval/extrinsics.h"
#include "common/eval/trajectory.h"
#include "eval_test_util.h"

namespace hs {
namespace {

const std::string kSample =
    HS_SOURCE_DIR "/tests/data/euroc_v1_01_static_sample/mav0/state_groundtruth_estimate0/data.csv";
const std::string kShared = HS_SOURCE_DIR "/../shared/data/euroc";

struct CliRun {
  int status = -1;
  std::string out, err;
};

CliRun run_eval(const std::string& args) {
  const std::string out = test::write_temp(""), err = test::write_temp("");
  CliRun r;
  const int raw =
      std::system((std::string(HS_EVAL_BIN) + " " + args + " >" + out + " 2>" + err).c_str());
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::stringstream o, e;
  o << std::ifstream(out).rdbuf();
  e << std::ifstream(err).rdbuf();
  r.out = o.str();
  r.err = e.str();
  std::remove(out.c_str());
  std::remove(err.c_str());
  return r;
}

nlohmann::json read_json(const std::string& path) {
  nlohmann::json j;
  std::ifstream(path) >> j;
  return j;
}

TEST(EvalCli, StaticSampleAgainstItselfGivesZeroError) {
  const std::string json = test::write_temp("", ".json");
  const CliRun r = run_eval(kSample + " " + kSample + " --align --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("matched 6 of max. 6"), std::string::npos) << r.out;
  const nlohmann::json j = read_json(json);
  EXPECT_EQ(j["matched"], 6);
  EXPECT_EQ(j["ground_truth_poses"], 6);
  EXPECT_EQ(j["alignment"]["mode"], "se3");
  EXPECT_LT(j["ape"]["rmse"].get<double>(), 1e-9);
  EXPECT_EQ(j["ape"]["count"], 6);
  EXPECT_EQ(j["rpe_trans"]["count"], 5);
  EXPECT_LT(j["rpe_rot"]["max"].get<double>(), 1e-6);
  std::remove(json.c_str());
}

TEST(EvalCli, StaticSampleShiftedInTimeAndSpace) {
  // TUM copy moved 1 m along x and stamped 0.5 s late: the offset restores association and the
  // unaligned APE is exactly the 1 m shift.
  Trajectory t = load_trajectory(kSample);
  for (StampedPose& p : t.poses) {
    p.T_w_b.translation().x() += 1.0;
    p.t_ns += 500'000'000;
  }
  const std::string est = test::write_temp(""), json = test::write_temp("", ".json");
  save_tum(est, t);
  EXPECT_EQ(run_eval(kSample + " " + est).status, 1);  // nothing within 10 ms
  const CliRun r = run_eval(kSample + " " + est + " --t-offset -0.5 --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = read_json(json);
  EXPECT_EQ(j["matched"], 6);
  EXPECT_NEAR(j["ape"]["rmse"].get<double>(), 1.0, 1e-8);
  EXPECT_NEAR(j["ape"]["std"].get<double>(), 0.0, 1e-8);
  std::remove(est.c_str());
  std::remove(json.c_str());
}

TEST(EvalCli, BadInputExitsNonZeroNamingFileAndLine) {
  const std::string bad = test::write_temp("1.0 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n");
  const CliRun r = run_eval(kSample + " " + bad);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(bad + ":2: duplicate timestamp"), std::string::npos) << r.err;
  std::remove(bad.c_str());
}

TEST(EvalCli, RealV101Sim3AndCameraFrame) {
  const std::string gt_path = kShared + "/groundtruth/V1_01_easy.csv";
  const std::string cam0 = kShared + "/calib/cam0.yaml";
  if (!std::filesystem::exists(gt_path) || !std::filesystem::exists(cam0))
    GTEST_SKIP() << "shared EuRoC data absent: " << gt_path;
  const Trajectory gt = load_trajectory(gt_path);
  std::mt19937 rng(1);

  // Monocular-like: camera poses in another world, at 0.4x scale.
  const Eigen::Isometry3d T_b_c = load_T_b_c_yaml(cam0);
  Trajectory est = test::transformed(gt, test::random_pose(rng, 5.0));
  for (StampedPose& p : est.poses) p.T_w_b = p.T_w_b * T_b_c;
  est = test::transformed(est, Eigen::Isometry3d::Identity(), 0.4);
  const std::string est_path = test::write_temp(""), json = test::write_temp("", ".json");
  const std::string plot = test::write_temp("", ".png"), aligned = test::write_temp("");
  save_tum(est_path, est);
  const CliRun r = run_eval(gt_path + " " + est_path + " --align --correct-scale --T-b-c " + cam0 +
                            " --json " + json + " --plot " + plot + " --save-aligned " + aligned);
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = read_json(json);
  EXPECT_EQ(j["matched"].get<size_t>(), gt.poses.size());
  EXPECT_NEAR(j["alignment"]["scale"].get<double>(), 2.5, 1e-6);
  EXPECT_LT(j["ape"]["rmse"].get<double>(), 1e-6);  // only TUM's 9 printed decimals remain
  EXPECT_LT(j["rpe_rot"]["rmse"].get<double>(), 1e-4);
  EXPECT_GT(std::filesystem::file_size(plot), 10000u);
  const Trajectory back = load_trajectory(aligned);
  ASSERT_EQ(back.poses.size(), gt.poses.size());
  EXPECT_TRUE(back.poses[10].T_w_b.isApprox(gt.poses[10].T_w_b, 1e-6));
  for (const std::string& f : {est_path, json, plot, aligned}) std::remove(f.c_str());
}

TEST(EvalCli, RealV101AgainstItselfSe3) {
  const std::string gt_path = kShared + "/groundtruth/V1_01_easy.csv";
  if (!std::filesystem::exists(gt_path)) GTEST_SKIP() << "shared EuRoC data absent: " << gt_path;
  std::mt19937 rng(2);
  const std::string est_path = test::write_temp(""), json = test::write_temp("", ".json");
  save_tum(est_path, test::transformed(load_trajectory(gt_path), test::random_pose(rng, 20.0)));
  const CliRun r = run_eval(gt_path + " " + est_path + " -a -d 1 -u m --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = read_json(json);
  EXPECT_LT(j["ape"]["rmse"].get<double>(), 1e-6);
  EXPECT_NEAR(j["alignment"]["scale"].get<double>(), 1.0, 0.0);
  EXPECT_GT(j["rpe_trans"]["count"].get<int>(), 10);  // V1_01 flies tens of metres
  std::remove(est_path.c_str());
  std::remove(json.c_str());
}

}  // namespace
}  // namespace hs
