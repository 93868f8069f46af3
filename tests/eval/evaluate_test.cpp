#include "common/eval/evaluate.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <opencv2/imgcodecs.hpp>

#include "common/core/error.h"
#include "common/eval/plot.h"
#include "eval_test_util.h"

namespace hs {
namespace {

TEST(Evaluate, CameraEstimateWithTbcShiftedInTimeAndWorld) {
  std::mt19937 rng(21);
  const Trajectory gt = test::figure_eight(400);  // body poses T_w_b, 20 Hz
  const Eigen::Isometry3d T_b_c = test::random_pose(rng, 0.1);
  const Eigen::Isometry3d T_v_w = test::random_pose(rng, 10.0);  // the estimator's own world
  Trajectory est = test::transformed(gt, T_v_w);
  for (StampedPose& p : est.poses) {
    p.T_w_b = p.T_w_b * T_b_c;  // camera poses
    p.t_ns -= 2'000'000'000;    // estimator clock 2 s behind
  }
  EvalOptions opt;
  opt.align = AlignMode::kSe3;
  opt.t_offset_ns = 2'000'000'000;
  opt.t_max_diff_ns = 1'000'000;
  opt.T_b_c = T_b_c;
  const EvalResult r = evaluate(gt, est, opt);
  EXPECT_EQ(r.matched.est.poses.size(), 400u);
  EXPECT_LT(r.ape.stats.max, 1e-9);
  EXPECT_LT(r.rpe_trans.stats.max, 1e-9);
  EXPECT_LT(r.rpe_rot.stats.max, 1e-7);
  EXPECT_EQ(r.rpe_trans.stats.count, 399u);

  // Without T_b_c the lever arm shows up as error.
  opt.T_b_c.reset();
  EXPECT_GT(evaluate(gt, est, opt).ape.stats.rmse, 1e-4);
}

TEST(Evaluate, Sim3ReportsScaleAndJson) {
  const Trajectory gt = test::figure_eight(200);
  const Trajectory est = test::transformed(gt, Eigen::Isometry3d::Identity(), 0.5);
  EvalOptions opt;
  opt.align = AlignMode::kSim3;
  opt.rpe_delta = 0.5;
  opt.rpe_delta_unit = DeltaUnit::kMeters;
  const EvalResult r = evaluate(gt, est, opt);
  EXPECT_NEAR(r.alignment.s, 2.0, 1e-9);
  EXPECT_LT(r.ape.stats.rmse, 1e-9);
  const nlohmann::json j = to_json(r);
  EXPECT_EQ(j["matched"], 200);
  EXPECT_EQ(j["alignment"]["mode"], "sim3");
  EXPECT_NEAR(j["alignment"]["scale"].get<double>(), 2.0, 1e-9);
  EXPECT_EQ(j["ape"]["pose_relation"], "trans_part");
  EXPECT_EQ(j["rpe_trans"]["delta_unit"], "m");
  EXPECT_EQ(j["rpe_rot"]["unit"], "deg");
  EXPECT_EQ(j["rpe_trans"]["count"].get<size_t>(), r.rpe_trans.stats.count);
  EXPECT_NE(summary_text(r).find("APE w.r.t. translation part (m)"), std::string::npos);
}

TEST(Evaluate, UnalignedErrorIsThePlainOffset) {
  const Trajectory gt = test::figure_eight(100);
  Eigen::Isometry3d shift = Eigen::Isometry3d::Identity();
  shift.translation() = Eigen::Vector3d(0.3, -0.4, 0.0);
  const EvalResult r = evaluate(gt, test::transformed(gt, shift), EvalOptions{});
  EXPECT_NEAR(r.ape.stats.rmse, 0.5, 1e-12);
  EXPECT_NEAR(r.ape.stats.std, 0.0, 1e-12);
  EXPECT_LT(r.rpe_trans.stats.max, 1e-12);  // a constant world offset has no relative error
}

TEST(Evaluate, NoMatchesIsInputError) {
  const Trajectory gt = test::figure_eight(10, 0);
  const Trajectory est = test::figure_eight(10, 100'000'000'000);
  EXPECT_THROW(evaluate(gt, est, EvalOptions{}), InputError);
}

TEST(Plot, WritesReadablePng) {
  const Trajectory gt = test::figure_eight(300);
  Trajectory est = gt;
  for (size_t i = 0; i < est.poses.size(); ++i)
    est.poses[i].T_w_b.translation().x() += 0.05 * std::sin(0.1 * static_cast<double>(i));
  EvalOptions opt;
  opt.align = AlignMode::kSe3;
  const EvalResult r = evaluate(gt, est, opt);
  const std::string p = test::write_temp("", ".png");
  write_plot(p, r, "unit test");
  const cv::Mat img = cv::imread(p);
  ASSERT_FALSE(img.empty());
  EXPECT_EQ(img.cols, 1200);
  EXPECT_EQ(img.rows, 1100);
  std::remove(p.c_str());
}

}  // namespace
}  // namespace hs
