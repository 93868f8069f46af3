#include "tracker/mono_initialiser.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "common/calib/camera_calib.h"
#include "common/dataset/euroc_reader.h"
#include "common/sim/dataset_gen.h"
#include "common/sim/scenario.h"

namespace hs {
namespace {

sim::Scenario scenario(const std::string& name, double duration_s) {
  sim::Scenario s = sim::load_scenario(HS_SOURCE_DIR "/config/sim/" + name + ".yaml");
  s.duration_s = duration_s;
  return s;
}

Eigen::Isometry3d T_w_c0(const sim::DatasetGenerator& gen, int64_t t_ns) {
  return gen.T_w_b(t_ns) * gen.scenario().camera.calib.cam0.T_b_c;
}

// room_mav's cam0 alone: waiting (and saying why) while the drone is still, then the two views
// reconstructed with the true rotation and direction of travel, points in front at the true
// depths up to the unknown scale.
TEST(MonoInitialiser, TheRoomIsReconstructedOnceTheDroneHasMovedEnough) {
  sim::DatasetGenerator gen(scenario("room_mav", 8.0));
  const PinholeRadtan& cam = gen.scenario().camera.calib.cam0.intrinsics;
  MonoInitialiser init(cam);
  MonoInitResult r;
  size_t i = 0;
  std::vector<std::string> reasons;
  for (; i < gen.num_frames() && !r.ok; ++i) {
    const sim::SimStereoFrame f = gen.frame(i);
    r = init.add_frame(f.t_ns, f.cam0);
    if (!r.ok) reasons.push_back(r.reason);
  }
  ASSERT_TRUE(r.ok) << "never initialised; last: " << reasons.back();
  EXPECT_FALSE(reasons.empty());
  const int64_t t_cur = gen.frame_times_ns()[i - 1];
  std::printf("initialised at frame %zu (%.2f s) from %.2f s: %zu points, %s, flow %.1f px\n",
              i - 1, ns_to_s(t_cur - gen.frame_times_ns()[0]),
              ns_to_s(r.ref_t_ns - gen.frame_times_ns()[0]), r.p_ref.size(),
              r.homography ? "homography" : "essential matrix", r.median_flow_px);
  const Eigen::Isometry3d truth = T_w_c0(gen, r.ref_t_ns).inverse() * T_w_c0(gen, t_cur);
  EXPECT_LT(
      Eigen::AngleAxisd(truth.linear().transpose() * r.T_ref_cur.linear()).angle() * 180 / M_PI,
      0.5);
  const double dir_deg =
      std::acos(
          std::clamp(truth.translation().normalized().dot(r.T_ref_cur.translation()), -1.0, 1.0)) *
      180 / M_PI;
  EXPECT_LT(dir_deg, 5.0);
  ASSERT_GE(r.p_ref.size(), 50u);
  // Depths: the scale is the true baseline.
  const double scale = truth.translation().norm();
  int near_truth = 0;
  for (size_t k = 0; k < r.p_ref.size(); ++k) {
    const Eigen::Vector3d p_c = scale * r.p_ref[k];
    Eigen::Vector2d uv;
    ASSERT_TRUE(cam.project(p_c, &uv));
    EXPECT_LT((uv - r.uv_ref[k]).norm(), 3.0);
    near_truth += p_c.z() > 0.3 && p_c.z() < 15.0;
  }
  EXPECT_GT(near_truth, 0.9 * r.p_ref.size());
}

// Nothing moves: no false start however long it waits; the reason names the missing motion.
TEST(MonoInitialiser, AStillCameraNeverInitialisesAndSaysWhy) {
  sim::DatasetGenerator gen(scenario("static", 4.0));
  MonoInitialiser init(gen.scenario().camera.calib.cam0.intrinsics);
  MonoInitResult r;
  for (size_t i = 0; i < gen.num_frames(); ++i) {
    const sim::SimStereoFrame f = gen.frame(i);
    r = init.add_frame(f.t_ns, f.cam0);
    ASSERT_FALSE(r.ok) << "frame " << i;
  }
  EXPECT_NE(r.reason.find("not enough motion"), std::string::npos) << r.reason;
  EXPECT_GT(r.tracked, 80);
}

const NavState& truth_near(const std::vector<NavState>& gt, int64_t t_ns) {
  const auto it = std::min_element(gt.begin(), gt.end(), [&](const NavState& a, const NavState& b) {
    return std::llabs(a.t_ns - t_ns) < std::llabs(b.t_ns - t_ns);
  });
  EXPECT_LT(std::llabs(it->t_ns - t_ns), 5'000'000) << "no ground truth near " << t_ns;
  return *it;
}

// The real flying frames of V1_01 (left camera): initialised within the first 60 frames (the
// issue's target), with the motion the ground truth gives.
TEST(MonoInitialiser, RealV1_01FlightInitialisesWithinSixtyFramesWithTheTrueMotion) {
  const std::string root = HS_SOURCE_DIR "/../shared/data/euroc/V1_01_flight_cam0";
  if (!std::filesystem::exists(root))
    GTEST_SKIP() << root << " absent (shared EuRoC pieces): covered by the simulated room above";
  EurocOptions eo;
  eo.use_cam1 = false;
  const EurocReader reader(root, eo);
  const StereoCalib calib = euroc_stereo_calib();
  MonoInitialiser init(calib.cam0.intrinsics);
  MonoInitResult r;
  size_t i = 0;
  std::string last;
  for (; i < std::min<size_t>(60, reader.frames().size()) && !r.ok; ++i) {
    r = init.add_frame(reader.frames()[i].t_ns, reader.load_frame(i).cam0);
    if (!r.ok) last = r.reason;
  }
  ASSERT_TRUE(r.ok) << "not initialised in 60 frames; last: " << last;
  const int64_t t_cur = reader.frames()[i - 1].t_ns;
  const auto T_w_c = [&](int64_t t) {
    return truth_near(reader.ground_truth(), t).T_w_b() * calib.cam0.T_b_c;
  };
  const Eigen::Isometry3d truth = T_w_c(r.ref_t_ns).inverse() * T_w_c(t_cur);
  const double rot_deg =
      Eigen::AngleAxisd(truth.linear().transpose() * r.T_ref_cur.linear()).angle() * 180 / M_PI;
  const double dir_deg =
      std::acos(
          std::clamp(truth.translation().normalized().dot(r.T_ref_cur.translation()), -1.0, 1.0)) *
      180 / M_PI;
  std::printf(
      "V1_01 flight: initialised at frame %zu from frame %s, %zu points, %s; rotation off %.2f "
      "deg, direction of travel off %.1f deg (true baseline %.1f cm)\n",
      i - 1, r.ref_t_ns == reader.frames()[0].t_ns ? "0" : "later", r.p_ref.size(),
      r.homography ? "homography" : "essential matrix", rot_deg, dir_deg,
      100 * truth.translation().norm());
  EXPECT_LT(rot_deg, 1.0);
  EXPECT_LT(dir_deg, 10.0);
}

// The real static frames of V1_01 (left camera): the drone stands on the floor, with image
// noise and flicker; no start however long.
TEST(MonoInitialiser, RealV1_01StaticFramesNeverInitialise) {
  const std::string root = HS_SOURCE_DIR "/../shared/data/euroc/V1_01_static_stereo";
  if (!std::filesystem::exists(root))
    GTEST_SKIP() << root << " absent (shared EuRoC pieces): covered by the simulated still camera";
  EurocOptions eo;
  eo.use_cam1 = false;
  const EurocReader reader(root, eo);
  MonoInitialiser init(euroc_stereo_calib().cam0.intrinsics);
  MonoInitResult r;
  for (size_t i = 0; i < reader.frames().size(); ++i) {
    r = init.add_frame(reader.frames()[i].t_ns, reader.load_frame(i).cam0);
    ASSERT_FALSE(r.ok) << "frame " << i;
  }
  EXPECT_GT(reader.frames().size(), 90u);
  EXPECT_NE(r.reason.find("not enough motion"), std::string::npos) << r.reason;
}

}  // namespace
}  // namespace hs
