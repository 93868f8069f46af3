// The observation check's along-track correlation on a hand-built graph: the same keyframes and
// points, keypoints off their true projections by independent noise or by noise that drifts
// along each track (AR(1)).
#include "mapper/offline/observation_check.h"

#include <gtest/gtest.h>

#include <iostream>
#include <random>
#include <unordered_map>

#include "../keyframe_test_util.h"
#include "mapper/keyframe_from_msg.h"

namespace hs {
namespace {

constexpr int kKeyframes = 30;
constexpr int kPoints = 60;
constexpr double kSigmaPx = 0.3;

// Camera sliding sideways 5 cm per keyframe past points 4-10 m ahead.
struct Scene {
  StereoCalib calib = euroc_stereo_calib();
  std::vector<Eigen::Isometry3d> T_w_b;
  std::vector<Eigen::Vector3d> p_w;

  Scene() {
    const Eigen::Isometry3d T_w_c0 = calib.cam0.T_b_c;  // body at the origin
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> x(-3.0, 3.0), y(-2.0, 2.0), z(4.0, 10.0);
    for (int i = 0; i < kPoints; ++i)
      p_w.push_back(T_w_c0 * Eigen::Vector3d(x(rng), y(rng), z(rng)));
    for (int k = 0; k < kKeyframes; ++k) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = T_w_c0.linear() * Eigen::Vector3d(0.05 * k, 0.0, 0.0);
      T_w_b.push_back(T);
    }
  }

  // Keypoints at the true cam0 projections plus per-point noise e_k = rho e_k-1 + sqrt(1 -
  // rho^2) w_k (stationary, sigma kSigmaPx per axis).
  KeyframeGraph graph(double rho, uint32_t seed) const {
    std::mt19937 rng(seed);
    std::normal_distribution<double> w(0.0, kSigmaPx);
    std::vector<Eigen::Vector2d> e(kPoints);
    for (auto& x : e) x = Eigen::Vector2d(w(rng), w(rng));
    KeyframeGraph g;
    for (int k = 0; k < kKeyframes; ++k) {
      std::vector<int64_t> ids = test::ids(0, kPoints - 1);
      hsslam::keyframe_t m = test::keyframe_msg(k, k - 1, ids);
      const Eigen::Quaterniond q(T_w_b[k].linear());
      for (int a = 0; a < 3; ++a) m.pose.p_w_b[a] = T_w_b[k].translation()[a];
      m.pose.q_w_b[0] = q.w(), m.pose.q_w_b[1] = q.x(), m.pose.q_w_b[2] = q.y(),
      m.pose.q_w_b[3] = q.z();
      const Eigen::Isometry3d T_c_w = (T_w_b[k] * calib.cam0.T_b_c).inverse();
      for (int i = 0; i < kPoints; ++i) {
        if (k > 0) e[i] = rho * e[i] + std::sqrt(1.0 - rho * rho) * Eigen::Vector2d(w(rng), w(rng));
        const Eigen::Vector2d uv = calib.cam0.intrinsics.project(T_c_w * p_w[i]) + e[i];
        hsslam::keypoint_t& kp = m.keypoints[i];
        kp.u = static_cast<float>(uv.x()), kp.v = static_cast<float>(uv.y());
        kp.u_right = kp.v_right = kp.depth = -1.f;
        for (int a = 0; a < 3; ++a) m.points[i].p_w[a] = p_w[i][a];
      }
      g.insert(keyframe_from_msg(m, "KEYFRAME"));
    }
    return g;
  }

  ObservationCheck check(const KeyframeGraph& g) const {
    std::unordered_map<int64_t, Eigen::Isometry3d> by_time;
    for (int k = 0; k < kKeyframes; ++k) by_time[test::keyframe_time(k)] = T_w_b[k];
    return check_observations(g, calib, [&](int64_t t_ns) -> std::optional<Eigen::Isometry3d> {
      const auto it = by_time.find(t_ns);
      return it == by_time.end() ? std::nullopt : std::optional<Eigen::Isometry3d>(it->second);
    });
  }
};

TEST(ObservationCheck, IndependentNoiseShowsNoCorrelationAlongTracks) {
  const Scene scene;
  const ObservationCheck c = scene.check(scene.graph(0.0, 1));
  EXPECT_EQ(c.points, kPoints);
  EXPECT_EQ(c.track.pairs, kPoints * (kKeyframes - 1));
  EXPECT_NEAR(c.camera[0].rms(), std::sqrt(2.0) * kSigmaPx, 0.05);
  EXPECT_LT(std::abs(c.track.lag1()), 0.1) << c.track.lag1();
}

TEST(ObservationCheck, NoiseDriftingAlongTracksIsMeasured) {
  const Scene scene;
  const double white = scene.check(scene.graph(0.0, 1)).track.lag1();
  const double drifting = scene.check(scene.graph(0.8, 1)).track.lag1();
  std::cout << "white " << white << " drifting " << drifting << "\n";
  EXPECT_GT(drifting, 0.5) << "white " << white;
  EXPECT_GT(drifting, white + 0.4);
}

}  // namespace
}  // namespace hs
