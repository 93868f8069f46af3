#include "common/sim/trajectory.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hs::sim {
namespace {

// Speed profile of the ramps: quintic smoothstep r(x) and its derivatives, whose integral over
// [0, 1] is 1/2. r'' vanishes at both ends, so the body jerk stays continuous.
double ramp_rate(double x) {
  return x * x * x * (10.0 + x * (-15.0 + 6.0 * x));
}
double ramp_rate_d1(double x) {
  return 30.0 * x * x * (1.0 - x) * (1.0 - x);
}
double ramp_rate_d2(double x) {
  return 60.0 * x * (1.0 - x) * (1.0 - 2.0 * x);
}
double ramp_integral(double x) {
  return x * x * x * x * (2.5 + x * (-3.0 + x));
}

Eigen::Matrix3d rot_z(double a) {
  return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).matrix();
}

}  // namespace

Eigen::Matrix3d euroc_R_vehicle_body() {
  Eigen::Matrix3d R;
  R.col(0) = Eigen::Vector3d::UnitZ();   // body x: up
  R.col(1) = -Eigen::Vector3d::UnitY();  // body y: right
  R.col(2) = Eigen::Vector3d::UnitX();   // body z: forward
  return R;
}

std::vector<Eigen::Vector3d> resample_polyline(const std::vector<Eigen::Vector3d>& waypoints,
                                               double spacing, bool closed) {
  if (waypoints.empty() || !(spacing > 0.0)) throw std::invalid_argument("resample_polyline");
  std::vector<Eigen::Vector3d> pts = waypoints;
  if (closed) pts.push_back(waypoints.front());
  std::vector<double> cum{0.0};
  for (size_t i = 1; i < pts.size(); ++i) cum.push_back(cum.back() + (pts[i] - pts[i - 1]).norm());
  const double length = cum.back();
  if (length == 0.0) return {waypoints.front()};
  const long n = std::max<long>(closed ? 6 : 1, std::lround(length / spacing));
  std::vector<Eigen::Vector3d> out;
  size_t seg = 1;
  for (long i = 0; i < n + (closed ? 0 : 1); ++i) {
    const double d = length * static_cast<double>(i) / static_cast<double>(n);
    while (seg + 1 < pts.size() && cum[seg] < d) ++seg;
    const double span = cum[seg] - cum[seg - 1];
    const double f = span > 0.0 ? (d - cum[seg - 1]) / span : 0.0;
    out.push_back(pts[seg - 1] + f * (pts[seg] - pts[seg - 1]));
  }
  return out;
}

Trajectory::Trajectory(const TrajectoryOptions& options)
    : opt_(options),
      path_(
          resample_polyline(options.waypoints, options.speed_mps * options.knot_s, options.closed),
          options.knot_s, options.closed) {
  if (!(opt_.speed_mps > 0.0) || !(opt_.knot_s > 0.0) || opt_.laps < 1 ||
      !(opt_.start_hold_s >= 0.0) || !(opt_.ramp_s > 0.0)) {
    throw std::invalid_argument("Trajectory: speed, knot, laps and ramp must be positive");
  }
  if (opt_.yaw_mode == YawMode::kHeading && !opt_.closed) {
    throw std::invalid_argument("Trajectory: heading yaw needs a closed path");
  }
  if (opt_.yaw_mode == YawMode::kKeyframes) {
    if (opt_.yaw_deg.empty() || !(opt_.yaw_knot_s > 0.0)) {
      throw std::invalid_argument("Trajectory: keyframe yaw needs keyframes and a knot > 0");
    }
    std::vector<Eigen::Matrix<double, 1, 1>> keys;
    for (double deg : opt_.yaw_deg) keys.emplace_back(deg * M_PI / 180.0);
    yaw_.emplace(keys, opt_.yaw_knot_s, false);
  }
  s_end_ = path_.length() * (opt_.closed ? opt_.laps : 1);
  ramp_s_ = std::min(opt_.ramp_s, s_end_);
}

double Trajectory::motion_end_s() const {
  return opt_.start_hold_s + ramp_s_ + s_end_;
}
double Trajectory::path_length_s() const {
  return path_.length();
}

Trajectory::Warp Trajectory::warp(double t_s) const {
  const double tau = t_s - opt_.start_hold_s;
  const double T = ramp_s_;
  const double cruise = s_end_ - T;
  Warp w;
  if (tau <= 0.0 || T <= 0.0) return w;
  if (tau < T) {
    const double x = tau / T;
    w.s = T * ramp_integral(x);
    w.ds = ramp_rate(x);
    w.dds = ramp_rate_d1(x) / T;
    w.ddds = ramp_rate_d2(x) / (T * T);
  } else if (tau < T + cruise) {
    w.s = 0.5 * T + (tau - T);
    w.ds = 1.0;
  } else if (tau < 2.0 * T + cruise) {
    const double y = (2.0 * T + cruise - tau) / T;  // runs from 1 down to 0
    w.s = s_end_ - T * ramp_integral(y);
    w.ds = ramp_rate(y);
    w.dds = -ramp_rate_d1(y) / T;
    w.ddds = ramp_rate_d2(y) / (T * T);
  } else {
    w.s = s_end_;
  }
  return w;
}

BodyKinematics Trajectory::at(double t_s) const {
  const Warp w = warp(t_s);
  const SplinePoint<3> P = path_.at(w.s);
  BodyKinematics k;
  k.p_w_b = P.value;
  k.v_w = P.d1 * w.ds;
  k.a_w = P.d2 * w.ds * w.ds + P.d1 * w.dds;
  const Eigen::Vector3d jerk_w =
      P.d3 * w.ds * w.ds * w.ds + 3.0 * P.d2 * w.ds * w.dds + P.d1 * w.ddds;

  double yaw = 0.0, yaw_rate = 0.0;
  if (yaw_) {
    const SplinePoint<1> Y = yaw_->at(w.s);
    yaw = Y.value(0);
    yaw_rate = Y.d1(0) * w.ds;
  } else {
    const double tx = P.d1.x(), ty = P.d1.y();
    yaw = std::atan2(ty, tx);
    yaw_rate = (tx * P.d2.y() - ty * P.d2.x()) / (tx * tx + ty * ty) * w.ds;
  }

  // Specific force in the yaw-rotated frame, and its time derivative.
  const Eigen::Matrix3d R_yaw = rot_z(yaw);
  const Eigen::Vector3d f = R_yaw.transpose() * (k.a_w + Eigen::Vector3d(0, 0, kGravityMps2));
  const Eigen::Vector3d f_dot =
      R_yaw.transpose() * jerk_w - yaw_rate * Eigen::Vector3d::UnitZ().cross(f);
  const double g = opt_.tilt_gain;
  const double pitch = g * std::atan2(f.x(), f.z());
  const double pitch_rate =
      g * (f.z() * f_dot.x() - f.x() * f_dot.z()) / (f.x() * f.x() + f.z() * f.z());
  const double h = std::hypot(f.x(), f.z());
  const double h_dot = (f.x() * f_dot.x() + f.z() * f_dot.z()) / h;
  const double roll = g * std::atan2(-f.y(), h);
  const double roll_rate = g * (f.y() * h_dot - h * f_dot.y()) / (f.y() * f.y() + h * h);

  const Eigen::Matrix3d R_w_v = R_yaw *
                                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()).matrix() *
                                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()).matrix();
  // ZYX Euler rates to vehicle-frame angular velocity.
  const double sr = std::sin(roll), cr = std::cos(roll), sp = std::sin(pitch), cp = std::cos(pitch);
  const Eigen::Vector3d omega_v(roll_rate - yaw_rate * sp, pitch_rate * cr + yaw_rate * cp * sr,
                                -pitch_rate * sr + yaw_rate * cp * cr);
  k.q_w_b = Eigen::Quaterniond(R_w_v * opt_.R_vehicle_body).normalized();
  k.omega_b = opt_.R_vehicle_body.transpose() * omega_v;
  return k;
}

}  // namespace hs::sim
