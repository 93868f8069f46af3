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
                         DescriptorMode mode = DescriptorMode::kHybrid, double skip_s = 0.0) {
  sim::Scenario scenario = sim::load_scenario(kSource + "/config/sim/" + scenario_name + ".yaml");
  scenario.duration_s = duration_s;
  TrackerOptions options;
  options.calib = scenario.camera.calib;
  options.descriptors = mode;
  sim::DatasetGenerator gen(scenario);
  OfflineRunOptions run_options;
  run_options.skip_ns = s_to_ns(skip_s);
  return run_offline(options, sim_source(gen), run_options);
}

// Angle between the estimated and the true gravity direction in the body frame (both world
// frames are gravity-aligned; yaw and origin may differ).
double gravity_error_deg(const Eigen::Quaterniond& q_w_b_est, const Eigen::Quaterniond& q_w_b_gt) {
  const Eigen::Vector3d down(0, 0, -1);
  const Eigen::Vector3d g_b_est = q_w_b_est.conjugate() * down;
  const Eigen::Vector3d g_b_gt = q_w_b_gt.conjugate() * down;
  return std::acos(std::clamp(g_b_est.dot(g_b_gt), -1.0, 1.0)) * 180.0 / M_PI;
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
  const NavState* gt = nullptr;
  for (const NavState& s : run.ground_truth)
    if (std::abs(s.t_ns - est.poses.back().t_ns) < 1'000'000) gt = &s;
  ASSERT_NE(gt, nullptr);
  EXPECT_LT(gravity_error_deg(Eigen::Quaterniond(est.poses.back().T_w_b.linear()), gt->q_w_b), 1.0);
}

// Started while driving straight at 4 m/s: the IMU alone looks static (constant velocity), the
// image shows motion, so the tracker aligns its visual poses with the IMU before it reports.
TEST(TrackerAccuracy, MovingStartAlignsGravityWithVisionAndImu) {
  const OfflineRunResult run = run_sim("vehicle_loop", 22.0, DescriptorMode::kHybrid, 10.0);
  ASSERT_FALSE(run.frames.empty());
  const auto first = std::find_if(run.frames.begin(), run.frames.end(), [](const FrameRecord& f) {
    return f.state != TrackState::kInitialising;
  });
  ASSERT_NE(first, run.frames.end());
  // 1 s of IMU history, then about 1 s of visual tracking before the alignment.
  EXPECT_LE(first->t_ns - run.frames.front().t_ns, 2'200'000'000);
  bool aligned = false;
  for (const FrameRecord& f : run.frames)
    aligned |= f.message.find("vision and IMU aligned") != std::string::npos;
  EXPECT_TRUE(aligned);
  size_t gt_i = 0;
  double worst_deg = 0.0;
  for (auto f = first; f != run.frames.end(); ++f) {
    ASSERT_EQ(f->state, TrackState::kTracking) << f->message;
    while (gt_i + 1 < run.ground_truth.size() && run.ground_truth[gt_i].t_ns < f->t_ns) ++gt_i;
    worst_deg = std::max(worst_deg, gravity_error_deg(f->nav.q_w_b, run.ground_truth[gt_i].q_w_b));
  }
  EXPECT_LT(worst_deg, 0.5);
  const auto eval = evaluate_run(run);
  ASSERT_TRUE(eval.has_value());
  EXPECT_LE(eval->ape.stats.rmse, 0.02) << summary_text(*eval);
}

}  // namespace
}  // namespace hs
