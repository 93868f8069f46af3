#include "common/imu/so3.h"

#include <cmath>

namespace hs::so3 {
namespace {

// Below this angle the closed forms lose digits to cancellation; their Taylor series (kept to
// theta^4) are exact to double precision there.
constexpr double kSmallAngle = 1e-2;

// sin(t)/t, (1 - cos(t))/t^2 and (t - sin(t))/t^3.
struct ExpCoefficients {
  double a, b, c;
};

ExpCoefficients exp_coefficients(double theta) {
  const double t2 = theta * theta;
  if (theta < kSmallAngle) {
    return {1.0 - t2 / 6.0 * (1.0 - t2 / 20.0), 0.5 - t2 / 24.0 * (1.0 - t2 / 30.0),
            1.0 / 6.0 - t2 / 120.0 * (1.0 - t2 / 42.0)};
  }
  const double s = std::sin(theta);
  const double c = std::cos(theta);
  return {s / theta, (1.0 - c) / t2, (theta - s) / (t2 * theta)};
}

}  // namespace

Eigen::Matrix3d hat(const Eigen::Vector3d& w) {
  Eigen::Matrix3d W;
  W << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return W;
}

Eigen::Vector3d vee(const Eigen::Matrix3d& W) {
  return 0.5 * Eigen::Vector3d(W(2, 1) - W(1, 2), W(0, 2) - W(2, 0), W(1, 0) - W(0, 1));
}

Eigen::Matrix3d exp(const Eigen::Vector3d& phi) {
  const ExpCoefficients k = exp_coefficients(phi.norm());
  const Eigen::Matrix3d W = hat(phi);
  return Eigen::Matrix3d::Identity() + k.a * W + k.b * W * W;
}

Eigen::Quaterniond exp_quat(const Eigen::Vector3d& phi) {
  const double half = 0.5 * phi.norm();
  // sin(half)/(2 half) keeps the vector part exact at small angles.
  const double h2 = half * half;
  const double k =
      half < kSmallAngle ? 0.5 * (1.0 - h2 / 6.0 * (1.0 - h2 / 20.0)) : 0.5 * std::sin(half) / half;
  return Eigen::Quaterniond(std::cos(half), k * phi.x(), k * phi.y(), k * phi.z());
}

Eigen::Vector3d log(const Eigen::Quaterniond& q_in) {
  Eigen::Quaterniond q = q_in.normalized();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // same rotation, angle in [0, pi]
  const double n = q.vec().norm();
  // theta / n with theta = 2 atan2(n, w); the series avoids 0/0 at the identity.
  const double k = n < 1e-6 ? 2.0 / q.w() * (1.0 - n * n / (3.0 * q.w() * q.w()))
                            : 2.0 * std::atan2(n, q.w()) / n;
  return k * q.vec();
}

// Eigen's matrix-to-quaternion conversion pivots on the largest diagonal term, which keeps the
// axis accurate near pi where the trace formula does not.
Eigen::Vector3d log(const Eigen::Matrix3d& R) {
  return log(Eigen::Quaterniond(R));
}

Eigen::Matrix3d right_jacobian(const Eigen::Vector3d& phi) {
  const ExpCoefficients k = exp_coefficients(phi.norm());
  const Eigen::Matrix3d W = hat(phi);
  return Eigen::Matrix3d::Identity() - k.b * W + k.c * W * W;
}

Eigen::Matrix3d right_jacobian_inverse(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const double t2 = theta * theta;
  // 1/t^2 - cot(t/2)/(2t): the half-angle form stays finite at t = pi.
  const double d = theta < kSmallAngle
                       ? 1.0 / 12.0 + t2 / 720.0 * (1.0 + t2 / 42.0)
                       : 1.0 / t2 - std::cos(0.5 * theta) / (2.0 * theta * std::sin(0.5 * theta));
  const Eigen::Matrix3d W = hat(phi);
  return Eigen::Matrix3d::Identity() + 0.5 * W + d * W * W;
}

}  // namespace hs::so3
