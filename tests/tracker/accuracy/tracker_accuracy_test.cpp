// End-to-end accuracy of the tracker alone (no mapper), with hs-eval's metrics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "tracker/offline/offline_run.h"
#include "tracker/offline/run_report.h"

namespace hs {
namespace {

const std::string kSource = HS_SOURCE_DIR;
const std::string kShared = kSource + "/../shared/data/euroc";

OfflineRunResult run_sim(const std::string& scenario_name, double duration_s,
                         DescriptorMode mode = DescriptorMode::kHybrid) {
  sim::Scenario scenario = sim::load_scenario(kSource + "/config/sim/" + scenario_name + ".yaml");
  scenario.duration_s = duration_s;
  TrackerOptions options;
  options.calib = scenario.camera.calib;
  options.descriptors = mode;
  sim::DatasetGenerator gen(scenario);
  return run_offline(options, sim_source(gen));
}

// The whole room_mav flight (40 s: 2 s at rest, then ~26 m of flying): the target is
// an ATE RMSE of at most 2 cm with every frame tracked.
TEST(TrackerAccuracy, RoomMavTracksEveryFrameWithinTwoCentimetres) {
  const OfflineRunResult run = run_sim("room_mav", 40.0);
  int initialising = 0;
  for (const FrameRecord& f : run.frames) {
    ASSERT_TRUE(f.accepted) << f.message;
    if (f.state == TrackState::kInitialising) {
      ++initialising;
      continue;
    }
    EXPECT_NE(f.state, TrackState::kLost) << "frame at " << f.t_ns << ": " << f.message;
  }
  EXPECT_LE(initialising, 21);  // one second of IMU history for gravity
  const auto eval = evaluate_run(run);
  ASSERT_TRUE(eval.has_value());
  EXPECT_LE(eval->ape.stats.rmse, 0.02) << summary_text(*eval);
  // Hybrid: descriptors only at keyframes, so most frames are direct.
  const TimingSummary t = summarise_timing(run);
  EXPECT_GT(t.non_keyframe.count, 2 * t.keyframe.count);
}

// Real EuRoC V1_01 before take-off: the estimate must stay put and level.
TEST(TrackerAccuracy, RealStaticStereoStaysStillAndLevel) {
  const std::string dir = kShared + "/V1_01_static_stereo";
  if (!std::filesystem::exists(dir))
    GTEST_SKIP() << dir << " not found (real EuRoC data is only in CI)";
  const EurocReader reader(dir);
  TrackerOptions options;
  options.calib = read_stereo_calib(reader.mav0());
  EurocStream stream(reader);
  const OfflineRunResult run = run_offline(options, euroc_source(stream));
  const Trajectory est = run.estimate();
  ASSERT_GT(est.poses.size(), 60u);
  const Eigen::Vector3d p0 = est.poses.front().T_w_b.translation();
  for (const StampedPose& p : est.poses)
    EXPECT_LT((p.T_w_b.translation() - p0).norm(), 0.005) << "at " << p.t_ns;

  // Gravity direction in the body frame, estimated vs ground truth, at the last frame.
  const Eigen::Matrix3d R_est = est.poses.back().T_w_b.linear();
  const NavState* gt = nullptr;
  for (const NavState& s : run.ground_truth)
    if (std::abs(s.t_ns - est.poses.back().t_ns) < 1'000'000) gt = &s;
  ASSERT_NE(gt, nullptr);
  const Eigen::Vector3d down(0, 0, -1);
  const Eigen::Vector3d g_b_est = R_est.transpose() * down;
  const Eigen::Vector3d g_b_gt = gt->q_w_b.toRotationMatrix().transpose() * down;
  const double angle_deg = std::acos(std::clamp(g_b_est.dot(g_b_gt), -1.0, 1.0)) * 180.0 / M_PI;
  EXPECT_LT(angle_deg, 1.0);
}

}  // namespace
}  // namespace hs
