#pragma once
// Synthetic observations for the pose optimiser tests: random map points in front of the
// stereo rig at a true body pose, seen with level-dependent pixel noise and a share of gross
// outliers. Deterministic for a given generator state.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "common/calib/camera_calib.h"
#include "common/imu/so3.h"
#include "tracker/pose_opt_types.h"

namespace hs::test {

struct SceneOptions {
  int num_observations = 200;
  double outlier_fraction = 0.2;
  double sigma0_px = 0.7;  // level-0 noise; level l has sigma0 * 1.2^l
  int max_level = 3;
  double min_depth_m = 2.0;
  double max_depth_m = 15.0;
  double noise_scale = 1.0;  // actual noise = noise_scale * the sigma the observation claims
};

struct Scene {
  std::vector<PoseObservation> observations;
  std::vector<bool> is_outlier;
  int num_outliers() const {
    int n = 0;
    for (bool o : is_outlier) n += o;
    return n;
  }
};

inline Eigen::Vector3d random_unit(std::mt19937* rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Vector3d(n(*rng), n(*rng), n(*rng)).normalized();
}

// Points seen by cam0 (and, for every other point that also projects into it, by cam1).
inline Scene make_scene(const StereoCalib& calib, const NavState& truth,
                        const SceneOptions& options, std::mt19937* rng) {
  const Eigen::Isometry3d T_w_b = Eigen::Translation3d(truth.p_w_b) * truth.q_w_b;
  const CameraCalib* cams[2] = {&calib.cam0, &calib.cam1};
  const PinholeRadtan& K0 = calib.cam0.intrinsics;
  std::uniform_real_distribution<double> u(20.0, K0.width - 20.0), v(20.0, K0.height - 20.0);
  std::uniform_real_distribution<double> depth(options.min_depth_m, options.max_depth_m);
  std::uniform_int_distribution<int> level(0, options.max_level);
  std::normal_distribution<double> noise(0.0, 1.0);
  Scene scene;
  for (int point = 0; static_cast<int>(scene.observations.size()) < options.num_observations;
       ++point) {
    const Eigen::Vector2d xy = K0.unproject_normalised({u(*rng), v(*rng)});
    const Eigen::Vector3d p_c0 = xy.homogeneous().eval() * depth(*rng);
    const Eigen::Vector3d p_w = T_w_b * calib.cam0.T_b_c * p_c0;
    for (int cam = 0; cam < 2; ++cam) {
      if (cam == 1 && point % 2 == 0) continue;
      if (static_cast<int>(scene.observations.size()) >= options.num_observations) break;
      const Eigen::Vector3d p_c = (T_w_b * cams[cam]->T_b_c).inverse() * p_w;
      Eigen::Vector2d uv;
      if (!cams[cam]->intrinsics.project(p_c, &uv)) continue;
      PoseObservation obs;
      obs.p_w = p_w;
      obs.camera = cam;
      obs.sigma_px = level_sigma_px(level(*rng), 1.2, options.sigma0_px);
      const double s = obs.sigma_px * options.noise_scale;
      obs.uv = uv + Eigen::Vector2d(noise(*rng), noise(*rng)) * s;
      scene.observations.push_back(obs);
      scene.is_outlier.push_back(false);
    }
  }
  // Gross outliers: a random share of the observations moved 20-80 px away.
  const int num_outliers =
      static_cast<int>(std::lround(options.outlier_fraction * options.num_observations));
  std::vector<int> order(scene.observations.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
  std::shuffle(order.begin(), order.end(), *rng);
  std::uniform_real_distribution<double> offset(20.0, 80.0), angle(0.0, 2.0 * EIGEN_PI);
  for (int k = 0; k < num_outliers; ++k) {
    const double a = angle(*rng);
    scene.observations[order[k]].uv += offset(*rng) * Eigen::Vector2d(std::cos(a), std::sin(a));
    scene.is_outlier[order[k]] = true;
  }
  return scene;
}

// `state` moved by exactly `translation_m` and turned by exactly `rotation_rad` (random axes).
inline NavState perturbed(const NavState& state, double translation_m, double rotation_rad,
                          std::mt19937* rng) {
  NavState s = state;
  s.p_w_b += translation_m * random_unit(rng);
  s.q_w_b = state.q_w_b * so3::exp_quat(rotation_rad * random_unit(rng));
  return s;
}

inline double rotation_error_rad(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return so3::log(a.inverse() * b).norm();
}

}  // namespace hs::test
