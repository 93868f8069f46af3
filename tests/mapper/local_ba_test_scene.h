#pragma once
// Synthetic local-BA windows for the tests and the bench: keyframes at a few Hz along the
// analytic trajectory of tests/imu/analytic_motion.h (exact IMU with a constant bias), points
// seeded in every keyframe's view at 2-8 m, seen by the EuRoC stereo rig with Gaussian pixel
// noise and a share of gross outliers. The input holds the true states; perturb() makes the
// initial guess. Deterministic for a given generator state.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "common/calib/camera_calib.h"
#include "common/imu/so3.h"
#include "mapper/local_ba.h"
#include "tests/imu/analytic_motion.h"
#include "tests/tracker/pose_opt_test_scene.h"  // random_unit, rotation_error_rad

namespace hs::test {

struct BaSceneOptions {
  int num_keyframes = 10;
  int64_t t0_ns = 1'000'000'000;
  int64_t keyframe_period_ns = 333'333'333;  // 3 Hz
  int64_t imu_period_ns = 5'000'000;         // 200 Hz
  int points_per_keyframe = 60;              // seeded in each keyframe's cam0 view
  int max_points_per_keyframe = 150;         // observed by each keyframe (stereo: both cameras)
  bool stereo = true;
  bool with_imu = true;
  double sigma_px = 1.0;
  double outlier_fraction = 0.02;  // of the observations, moved 20-50 px
  ImuBias true_bias{Eigen::Vector3d(0.004, -0.003, 0.005), Eigen::Vector3d(0.05, -0.08, 0.06)};
};

struct BaScene {
  LocalBaInput input;            // true states and points, noisy observations
  std::vector<bool> is_outlier;  // per observation
};

inline BaScene make_ba_scene(const StereoCalib& calib, const BaSceneOptions& options,
                             std::mt19937* rng) {
  const AnalyticMotion motion;
  BaScene scene;
  LocalBaInput& in = scene.input;
  for (int k = 0; k < options.num_keyframes; ++k) {
    const int64_t t_ns = options.t0_ns + k * options.keyframe_period_ns;
    in.keyframes.push_back({100 + k, motion.state(t_ns, options.true_bias), false});
  }
  // Points in front of each keyframe's cam0.
  const PinholeRadtan& K0 = calib.cam0.intrinsics;
  std::uniform_real_distribution<double> u(10.0, K0.width - 10.0), v(10.0, K0.height - 10.0);
  std::uniform_real_distribution<double> depth(2.0, 8.0);
  for (const BaKeyframe& kf : in.keyframes) {
    const Eigen::Isometry3d T_w_c0 = kf.state.T_w_b() * calib.cam0.T_b_c;
    for (int n = 0; n < options.points_per_keyframe; ++n) {
      const Eigen::Vector2d xy = K0.unproject_normalised({u(*rng), v(*rng)});
      const Eigen::Vector3d p_w = T_w_c0 * (xy.homogeneous().eval() * depth(*rng));
      in.points.push_back({static_cast<int64_t>(in.points.size()), p_w, false});
    }
  }
  // Each keyframe sees up to max_points_per_keyframe of the points that project into cam0.
  std::normal_distribution<double> noise(0.0, options.sigma_px);
  const CameraCalib* cams[2] = {&calib.cam0, &calib.cam1};
  std::vector<size_t> order(in.points.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  for (const BaKeyframe& kf : in.keyframes) {
    std::shuffle(order.begin(), order.end(), *rng);
    int seen = 0;
    for (size_t idx : order) {
      if (seen >= options.max_points_per_keyframe) break;
      const BaPoint& pt = in.points[idx];
      Eigen::Vector2d uv[2];
      const auto sees = [&](int cam) {
        const Eigen::Vector3d p_c = (kf.state.T_w_b() * cams[cam]->T_b_c).inverse() * pt.p_w;
        return p_c.z() > 0.5 && cams[cam]->intrinsics.project(p_c, &uv[cam]);
      };
      if (!sees(0)) continue;
      ++seen;
      for (int cam = 0; cam < 2; ++cam) {
        if (cam == 1 && !(options.stereo && sees(1))) continue;
        const Eigen::Vector2d noisy = uv[cam] + Eigen::Vector2d(noise(*rng), noise(*rng));
        in.observations.push_back({kf.id, pt.id, cam, noisy, options.sigma_px});
      }
    }
  }
  scene.is_outlier.assign(in.observations.size(), false);
  std::vector<size_t> obs_order(in.observations.size());
  for (size_t k = 0; k < obs_order.size(); ++k) obs_order[k] = k;
  std::shuffle(obs_order.begin(), obs_order.end(), *rng);
  const auto num_outliers =
      static_cast<size_t>(std::lround(options.outlier_fraction * in.observations.size()));
  std::uniform_real_distribution<double> offset(20.0, 50.0), angle(0.0, 2.0 * EIGEN_PI);
  for (size_t k = 0; k < num_outliers; ++k) {
    const double a = angle(*rng);
    in.observations[obs_order[k]].uv += offset(*rng) * Eigen::Vector2d(std::cos(a), std::sin(a));
    scene.is_outlier[obs_order[k]] = true;
  }
  // Exact IMU between consecutive keyframes, preintegrated at a zero bias estimate.
  if (options.with_imu) {
    const std::vector<ImuSample> samples =
        motion.samples(0, options.t0_ns + options.num_keyframes * options.keyframe_period_ns,
                       options.imu_period_ns, options.true_bias);
    for (size_t k = 1; k < in.keyframes.size(); ++k) {
      const NavState& a = in.keyframes[k - 1].state;
      const NavState& b = in.keyframes[k].state;
      in.imu_factors.push_back({in.keyframes[k - 1].id, in.keyframes[k].id,
                                preintegrate(samples, a.t_ns, b.t_ns, ImuBias{})});
    }
  }
  return scene;
}

// The initial guess: free keyframes moved by translation_m and turned by rotation_rad (random
// directions), velocities off by velocity_mps, biases zero; free points moved by point_m.
inline void perturb(LocalBaInput* in, double translation_m, double rotation_rad,
                    double velocity_mps, double point_m, std::mt19937* rng) {
  for (BaKeyframe& kf : in->keyframes) {
    if (kf.fixed) continue;
    kf.state.p_w_b += translation_m * random_unit(rng);
    kf.state.q_w_b = kf.state.q_w_b * so3::exp_quat(rotation_rad * random_unit(rng));
    kf.state.v_w += velocity_mps * random_unit(rng);
    kf.state.gyro_bias.setZero();
    kf.state.accel_bias.setZero();
  }
  for (BaPoint& pt : in->points) {
    if (!pt.fixed) pt.p_w += point_m * random_unit(rng);
  }
}

}  // namespace hs::test
