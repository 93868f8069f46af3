#pragma once
// Gravity direction, roll/pitch and gyro bias from a window of IMU samples taken at rest.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "common/core/types.h"
#include "common/imu/imu_options.h"

namespace hs {

struct StaticInitResult {
  bool ok = false;     // the window passed the static checks
  std::string reason;  // why it did not; empty when ok
  // Estimates from the window (filled whenever it has finite samples, even when !ok).
  Eigen::Vector3d gravity_dir_b = Eigen::Vector3d::Zero();  // unit, pointing down, body frame
  double roll = 0.0;   // rad, ZYX Euler angles of the body with yaw = 0
  double pitch = 0.0;  // rad
  Eigen::Quaterniond q_w_b = Eigen::Quaterniond::Identity();  // yaw = 0
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();        // mean gyro, rad/s
  // Statistics the checks used, over the means of complete static_block_ns blocks.
  int samples_used = 0;  // finite samples
  int blocks = 0;
  double accel_norm_mean = 0.0;
  double accel_norm_std = 0.0;
  Eigen::Vector3d gyro_std = Eigen::Vector3d::Zero();
};

// At rest the accelerometer measures -g in the body frame, so gravity points along minus the
// mean specific force; the gyro bias is the mean angular rate (both over all finite samples).
// The window is static when it spans options.static_min_duration_ns and the block-mean |accel|
// and gyro axes vary less than the options' thresholds. Non-finite samples are ignored.
StaticInitResult initialise_from_static(const std::vector<ImuSample>& window,
                                        const ImuOptions& options = {});

}  // namespace hs
