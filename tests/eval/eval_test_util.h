#pragma once
// Shared helpers for the eval tests: temp files and synthetic trajectories.
#include <unistd.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>
#include <string>

#include "common/eval/trajectory.h"

namespace hs::test {

// A fresh file under /tmp holding `content`; `suffix` e.g. ".csv".
inline std::string write_temp(const std::string& content, const std::string& suffix = ".txt") {
  std::string name = "/tmp/hs_eval_XXXXXX" + suffix;
  const int fd = mkstemps(name.data(), static_cast<int>(suffix.size()));
  if (fd < 0) std::abort();
  close(fd);
  std::ofstream(name) << content;
  return name;
}

inline Eigen::Isometry3d random_pose(std::mt19937& rng, double max_translation) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized())
                   .toRotationMatrix();
  T.translation() = max_translation * Eigen::Vector3d(u(rng), u(rng), u(rng));
  return T;
}

// A 3D figure-of-eight with turning orientation, `n` poses every `dt_ns`.
inline Trajectory figure_eight(size_t n, int64_t t0_ns = 1'000'000'000,
                               int64_t dt_ns = 50'000'000) {
  Trajectory traj;
  for (size_t i = 0; i < n; ++i) {
    const double s = 0.05 * static_cast<double>(i);
    StampedPose p;
    p.t_ns = t0_ns + static_cast<int64_t>(i) * dt_ns;
    p.T_w_b.translation() =
        Eigen::Vector3d(3.0 * std::sin(s), 2.0 * std::sin(2 * s), 0.5 * std::cos(s));
    p.T_w_b.linear() = (Eigen::AngleAxisd(s, Eigen::Vector3d::UnitZ()) *
                        Eigen::AngleAxisd(0.3 * std::sin(s), Eigen::Vector3d::UnitX()))
                           .toRotationMatrix();
    traj.poses.push_back(p);
  }
  return traj;
}

// Applies T on the left of every pose, optionally scaling positions first (a Sim(3)).
inline Trajectory transformed(const Trajectory& in, const Eigen::Isometry3d& T,
                              double scale = 1.0) {
  Trajectory out = in;
  for (StampedPose& p : out.poses) {
    p.T_w_b.translation() *= scale;
    p.T_w_b = T * p.T_w_b;
  }
  return out;
}

}  // namespace hs::test
