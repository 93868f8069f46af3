#pragma once
// A smooth body trajectory with closed-form position, velocity, acceleration, attitude and
// body angular rate, and exact IMU samples generated from it. Independent of hs::so3 so that it
// can check that code.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <vector>

#include "common/core/types.h"
#include "common/imu/imu_residual.h"

namespace hs::test {

class AnalyticMotion {
 public:
  // Position: sinusoids (a few metres, up to ~2 m/s^2). Attitude: R = Rz(yaw) Ry(pitch) Rx(roll)
  // with sinusoidal angles (body rates up to ~1.5 rad/s).
  Eigen::Vector3d p(double t) const {
    return {2.0 * std::sin(0.7 * t), 1.5 * std::cos(0.5 * t), 0.5 * std::sin(1.1 * t + 0.3)};
  }
  Eigen::Vector3d v(double t) const {
    return {1.4 * std::cos(0.7 * t), -0.75 * std::sin(0.5 * t), 0.55 * std::cos(1.1 * t + 0.3)};
  }
  Eigen::Vector3d a(double t) const {
    return {-0.98 * std::sin(0.7 * t), -0.375 * std::cos(0.5 * t),
            -0.605 * std::sin(1.1 * t + 0.3)};
  }
  // Euler angles (yaw, pitch, roll) and their rates.
  Eigen::Vector3d angles(double t) const {
    return {0.3 + 1.2 * std::sin(0.6 * t), 0.4 * std::sin(0.9 * t + 0.5), 0.5 * std::cos(1.3 * t)};
  }
  Eigen::Vector3d angle_rates(double t) const {
    return {0.72 * std::cos(0.6 * t), 0.36 * std::cos(0.9 * t + 0.5), -0.65 * std::sin(1.3 * t)};
  }
  Eigen::Matrix3d R(double t) const {
    const Eigen::Vector3d e = angles(t);
    return (Eigen::AngleAxisd(e[0], Eigen::Vector3d::UnitZ()) *
            Eigen::AngleAxisd(e[1], Eigen::Vector3d::UnitY()) *
            Eigen::AngleAxisd(e[2], Eigen::Vector3d::UnitX()))
        .toRotationMatrix();
  }
  // Body angular rate: each Euler rate rotated into the body frame by the later rotations.
  Eigen::Vector3d omega_b(double t) const {
    const Eigen::Vector3d e = angles(t);
    const Eigen::Vector3d r = angle_rates(t);
    const Eigen::Matrix3d Rx = Eigen::AngleAxisd(e[2], Eigen::Vector3d::UnitX()).toRotationMatrix();
    const Eigen::Matrix3d Ry = Eigen::AngleAxisd(e[1], Eigen::Vector3d::UnitY()).toRotationMatrix();
    return Rx.transpose() * Ry.transpose() * Eigen::Vector3d(0, 0, r[0]) +
           Rx.transpose() * Eigen::Vector3d(0, r[1], 0) + Eigen::Vector3d(r[2], 0, 0);
  }

  NavState state(int64_t t_ns, const ImuBias& bias = {}) const {
    const double t = ns_to_s(t_ns);
    NavState s;
    s.t_ns = t_ns;
    s.p_w_b = p(t);
    s.q_w_b = Eigen::Quaterniond(R(t));
    s.v_w = v(t);
    s.gyro_bias = bias.gyro;
    s.accel_bias = bias.accel;
    return s;
  }

  // Exact (biased) measurements at t_ns.
  ImuSample sample(int64_t t_ns, const ImuBias& bias = {}) const {
    const double t = ns_to_s(t_ns);
    ImuSample s;
    s.t_ns = t_ns;
    s.gyro = omega_b(t) + bias.gyro;
    s.accel = R(t).transpose() * (a(t) - default_gravity_w()) + bias.accel;
    return s;
  }

  // Samples every period_ns covering [t0_ns, t1_ns].
  std::vector<ImuSample> samples(int64_t t0_ns, int64_t t1_ns, int64_t period_ns,
                                 const ImuBias& bias = {}) const {
    std::vector<ImuSample> out;
    for (int64_t t = t0_ns; t < t1_ns + period_ns; t += period_ns) out.push_back(sample(t, bias));
    return out;
  }
};

}  // namespace hs::test
