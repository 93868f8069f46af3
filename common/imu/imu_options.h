#pragma once
// Options of the IMU module: the sensor noise model plus integration and static-detection
// thresholds. Defaults are the EuRoC ADIS16448 values (imu0.yaml).
#include <cstdint>

namespace hs {

// Continuous-time noise densities, as in Kalibr / EuRoC sensor.yaml files.
struct ImuNoise {
  double gyro_noise_density = 1.6968e-04;  // rad/s/sqrt(Hz)
  double gyro_random_walk = 1.9393e-05;    // rad/s^2/sqrt(Hz)
  double accel_noise_density = 2.0e-3;     // m/s^2/sqrt(Hz)
  double accel_random_walk = 3.0e-3;       // m/s^3/sqrt(Hz)
  double rate_hz = 200.0;  // nominal; per-sample white noise sigma = density * sqrt(rate_hz)
};

struct ImuOptions {
  ImuNoise noise;
  // Consecutive samples further apart than this (or a window end further than this from the
  // nearest sample) are reported as an IMU gap. Default: two samples missing at 200 Hz.
  int64_t max_gap_ns = 15'000'000;
  // Preintegration is redone from the raw samples once the gyro bias estimate moves further than
  // this from the linearisation point (rad/s). The accelerometer bias enters the deltas linearly,
  // so its first-order correction is exact and needs no threshold.
  double reintegrate_gyro_bias_change = 0.01;
  // Static window check. The statistics are taken over means of consecutive blocks of
  // static_block_ns, which average out motor/propeller vibration (a MAV waiting on the ground
  // vibrates by ~0.5 m/s^2 sample to sample) but not body motion. Thresholds: standard deviation
  // of the block-mean |accel| (m/s^2) and of each block-mean gyro axis (rad/s).
  int64_t static_block_ns = 100'000'000;
  double static_max_accel_norm_std = 0.1;
  double static_max_gyro_std = 0.01;
  int64_t static_min_duration_ns = 1'000'000'000;
};

}  // namespace hs
