#include "common/imu/static_init.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hs {
namespace {

// Running mean and (population) standard deviation.
template <typename T>
struct Moments {
  T sum, sum_sq;
  int n = 0;
  explicit Moments(const T& zero) : sum(zero), sum_sq(zero) {}
  void add(const T& x) {
    sum += x;
    sum_sq += x * x;
    ++n;
  }
};

}  // namespace

StaticInitResult initialise_from_static(const std::vector<ImuSample>& window,
                                        const ImuOptions& options) {
  StaticInitResult res;
  Eigen::Vector3d accel_sum = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_sum = Eigen::Vector3d::Zero();
  // Block means: the current block and the statistics over completed blocks.
  Eigen::Vector3d block_accel = Eigen::Vector3d::Zero();
  Eigen::Vector3d block_gyro = Eigen::Vector3d::Zero();
  int block_n = 0;
  int64_t block_index = 0;
  Moments<double> norm_moments(0.0);
  Moments<Eigen::Array3d> gyro_moments(Eigen::Array3d::Zero());
  int64_t t_first = 0, t_last = 0;

  for (const ImuSample& s : window) {
    if (!s.gyro.allFinite() || !s.accel.allFinite()) continue;
    if (res.samples_used == 0) t_first = s.t_ns;
    t_last = s.t_ns;
    ++res.samples_used;
    accel_sum += s.accel;
    gyro_sum += s.gyro;
    const int64_t index = (s.t_ns - t_first) / std::max<int64_t>(options.static_block_ns, 1);
    if (index != block_index && block_n > 0) {
      norm_moments.add((block_accel / block_n).norm());
      gyro_moments.add((block_gyro / block_n).array());
      block_accel.setZero();
      block_gyro.setZero();
      block_n = 0;
    }
    block_index = index;
    block_accel += s.accel;
    block_gyro += s.gyro;
    ++block_n;
  }
  const int n = res.samples_used;
  if (n == 0) {
    res.reason = "no finite IMU samples in the window";
    return res;
  }
  res.gyro_bias = gyro_sum / n;
  const Eigen::Vector3d up_b = accel_sum.normalized();
  res.gravity_dir_b = -up_b;
  // With yaw = 0, R_w_b^T * e_z = (-sin(pitch), sin(roll) cos(pitch), cos(roll) cos(pitch)).
  res.pitch = std::atan2(-up_b.x(), std::hypot(up_b.y(), up_b.z()));
  res.roll = std::atan2(up_b.y(), up_b.z());
  res.q_w_b = Eigen::AngleAxisd(res.pitch, Eigen::Vector3d::UnitY()) *
              Eigen::AngleAxisd(res.roll, Eigen::Vector3d::UnitX());

  // Statistics over the completed blocks (the trailing, possibly partial one is left out).
  res.blocks = norm_moments.n;
  if (res.blocks > 0) {
    const double m = norm_moments.sum / res.blocks;
    res.accel_norm_mean = m;
    res.accel_norm_std = std::sqrt(std::max(0.0, norm_moments.sum_sq / res.blocks - m * m));
    const Eigen::Array3d g = gyro_moments.sum / res.blocks;
    res.gyro_std = (gyro_moments.sum_sq / res.blocks - g * g).max(0.0).sqrt().matrix();
  }

  std::ostringstream why;
  if (t_last - t_first < options.static_min_duration_ns || res.blocks < 2) {
    why << "window spans " << ns_to_s(t_last - t_first) << " s (" << res.blocks
        << " blocks), shorter than " << ns_to_s(options.static_min_duration_ns) << " s";
  } else if (res.accel_norm_std > options.static_max_accel_norm_std) {
    why << "accelerometer norm std " << res.accel_norm_std << " m/s^2 exceeds "
        << options.static_max_accel_norm_std;
  } else if (res.gyro_std.maxCoeff() > options.static_max_gyro_std) {
    why << "gyro std " << res.gyro_std.maxCoeff() << " rad/s exceeds "
        << options.static_max_gyro_std;
  }
  res.reason = why.str();
  res.ok = res.reason.empty();
  return res;
}

}  // namespace hs
