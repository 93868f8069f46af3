#pragma once
// Plain measurement and state structs shared by every process. Timestamps are int64 ns.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace hs {

struct ImuSample {
  int64_t t_ns = 0;
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();   // rad/s, IMU frame
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();  // m/s^2, specific force, IMU frame
};

// Body (IMU) state in the world frame, as in EuRoC's state_groundtruth_estimate0.
struct NavState {
  int64_t t_ns = 0;
  Eigen::Vector3d p_w_b = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_w_b = Eigen::Quaterniond::Identity();
  Eigen::Vector3d v_w = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();

  Eigen::Isometry3d T_w_b() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q_w_b.toRotationMatrix();
    T.translation() = p_w_b;
    return T;
  }
  void set_T_w_b(const Eigen::Isometry3d& T) {
    q_w_b = Eigen::Quaterniond(T.linear()).normalized();
    p_w_b = T.translation();
  }
};

// The same state in a world frame rotated by R_new_old (biases are body-frame: unchanged).
inline NavState rotated(const NavState& x, const Eigen::Matrix3d& R_new_old) {
  NavState y = x;
  y.q_w_b = Eigen::Quaterniond(R_new_old * x.q_w_b.toRotationMatrix()).normalized();
  y.p_w_b = R_new_old * x.p_w_b;
  y.v_w = R_new_old * x.v_w;
  return y;
}

// The same state in a world frame moved by T_new_old.
inline NavState transformed(const NavState& x, const Eigen::Isometry3d& T_new_old) {
  NavState y = rotated(x, T_new_old.linear());
  y.p_w_b += T_new_old.translation();
  return y;
}

constexpr double kNsPerSec = 1e9;
inline double ns_to_s(int64_t t_ns) {
  return static_cast<double>(t_ns) * 1e-9;
}
inline int64_t s_to_ns(double t_s) {
  return static_cast<int64_t>(t_s * 1e9 + (t_s >= 0 ? 0.5 : -0.5));
}

}  // namespace hs
