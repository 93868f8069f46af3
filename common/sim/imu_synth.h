#pragma once
// IMU synthesis from an analytic trajectory: gyro = body angular rate, accel = R_w_b^T (a_w - g_w),
// plus white noise (density / sqrt(dt)) and bias random walks (density * sqrt(dt) per sample).
// The ground truth carries the true biases at every sample.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "common/core/types.h"
#include "common/sim/trajectory.h"

namespace hs::sim {

// Closed time interval [start_ns, end_ns].
struct TimeWindow {
  int64_t start_ns = 0;
  int64_t end_ns = 0;
  bool contains(int64_t t_ns) const { return t_ns >= start_ns && t_ns <= end_ns; }
};

struct ImuSynthOptions {
  double rate_hz = 200.0;
  // EuRoC ADIS16448 values (imu0/sensor.yaml).
  double gyro_noise_density = 1.6968e-04;               // rad/s/sqrt(Hz)
  double gyro_random_walk = 1.9393e-05;                 // rad/s^2/sqrt(Hz)
  double accel_noise_density = 2.0e-3;                  // m/s^2/sqrt(Hz)
  double accel_random_walk = 3.0e-3;                    // m/s^3/sqrt(Hz)
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();  // at the first sample
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();
  // Samples strictly inside a gap are not emitted (the samples at its ends are): a gap of
  // [t, t + 0.5 s] leaves exactly 0.5 s between consecutive samples. Biases keep drifting.
  // Times relative to the first sample.
  std::vector<TimeWindow> gaps;
};

struct ImuSeries {
  std::vector<ImuSample> samples;  // without the gaps
  std::vector<NavState> truth;     // at every sample time, gaps included
};

int64_t imu_period_ns(double rate_hz);

// Samples at t0_ns + k * period for every such time <= t_end_ns; trajectory time t_s is
// measured from t0_ns. Deterministic given `seed`.
ImuSeries synthesize_imu(const Trajectory& trajectory, const ImuSynthOptions& options,
                         int64_t t0_ns, int64_t t_end_ns, uint64_t seed);

// Noise-free specific force and angular rate of the body at one instant.
ImuSample ideal_imu(const BodyKinematics& k, int64_t t_ns);

}  // namespace hs::sim
