#include "common/imu/preintegration.h"

#include <algorithm>
#include <stdexcept>

#include "common/imu/so3.h"

namespace hs {

ImuPreintegration::ImuPreintegration(int64_t t0_ns, const ImuBias& bias, const ImuOptions& options)
    : options_(options), bias_(bias), t0_ns_(t0_ns), t1_ns_(t0_ns) {
  reset();
}

void ImuPreintegration::reset() {
  t1_ns_ = t0_ns_;
  delta_ = ImuDelta{};
  cov_.setZero();
  dR_dbg_.setZero();
  dv_dbg_.setZero();
  dv_dba_.setZero();
  dp_dbg_.setZero();
  dp_dba_.setZero();
}

void ImuPreintegration::integrate(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel,
                                  int64_t dt_ns) {
  if (dt_ns <= 0) throw std::invalid_argument("ImuPreintegration::integrate: dt_ns must be > 0");
  steps_.push_back({gyro, accel, dt_ns});
  propagate(steps_.back());
}

void ImuPreintegration::propagate(const Step& step) {
  const double dt = ns_to_s(step.dt_ns);
  const double dt2 = dt * dt;
  const Eigen::Vector3d w = step.gyro - bias_.gyro;
  const Eigen::Vector3d a = step.accel - bias_.accel;
  const Eigen::Matrix3d E = so3::exp(w * dt);
  const Eigen::Matrix3d E_half = so3::exp(0.5 * w * dt);
  const Eigen::Matrix3d Jr = so3::right_jacobian(w * dt);
  const Eigen::Matrix3d Jr_half = so3::right_jacobian(0.5 * w * dt);
  // Midpoint rotation: the velocity and position increments use the attitude half-way through
  // the step, which makes the scheme second-order accurate.
  const Eigen::Matrix3d R_mid = delta_.R * E_half;
  const Eigen::Matrix3d R_mid_ax = R_mid * so3::hat(a);

  // Bias Jacobians (the velocity ones before they are overwritten).
  const Eigen::Matrix3d dRmid_dbg = E_half.transpose() * dR_dbg_ - 0.5 * dt * Jr_half;
  dp_dbg_ += dv_dbg_ * dt - 0.5 * dt2 * R_mid_ax * dRmid_dbg;
  dp_dba_ += dv_dba_ * dt - 0.5 * dt2 * R_mid;
  dv_dbg_ -= dt * R_mid_ax * dRmid_dbg;
  dv_dba_ -= dt * R_mid;
  dR_dbg_ = E.transpose() * dR_dbg_ - dt * Jr;

  // Noise propagation: cov <- A cov A^T + B Q B^T, Q the discretised white noise of the step.
  Matrix9d A = Matrix9d::Identity();
  A.block<3, 3>(0, 0) = E.transpose();
  A.block<3, 3>(3, 0) = -dt * R_mid_ax * E_half.transpose();
  A.block<3, 3>(6, 0) = -0.5 * dt2 * R_mid_ax * E_half.transpose();
  A.block<3, 3>(6, 3) = dt * Eigen::Matrix3d::Identity();
  Eigen::Matrix<double, 9, 6> B = Eigen::Matrix<double, 9, 6>::Zero();
  B.block<3, 3>(0, 0) = dt * Jr;
  B.block<3, 3>(3, 0) = -0.5 * dt2 * R_mid_ax * Jr_half;
  B.block<3, 3>(3, 3) = dt * R_mid;
  B.block<3, 3>(6, 0) = -0.25 * dt2 * dt * R_mid_ax * Jr_half;
  B.block<3, 3>(6, 3) = 0.5 * dt2 * R_mid;
  const double var_g = options_.noise.gyro_noise_density * options_.noise.gyro_noise_density / dt;
  const double var_a = options_.noise.accel_noise_density * options_.noise.accel_noise_density / dt;
  Eigen::Matrix<double, 9, 6> BQ = B;
  BQ.leftCols<3>() *= var_g;
  BQ.rightCols<3>() *= var_a;
  cov_ = A * cov_ * A.transpose() + BQ * B.transpose();

  delta_.p += delta_.v * dt + 0.5 * dt2 * R_mid * a;
  delta_.v += dt * R_mid * a;
  delta_.R = delta_.R * E;
  t1_ns_ += step.dt_ns;
}

void ImuPreintegration::append(const ImuPreintegration& later) {
  if (later.t0_ns_ != t1_ns_) {
    throw std::invalid_argument("ImuPreintegration::append: windows are not consecutive");
  }
  for (const Step& step : later.steps_) {
    steps_.push_back(step);
    propagate(step);
  }
  status_.nonfinite_rejected += later.status_.nonfinite_rejected;
  status_.nonpositive_dt_skipped += later.status_.nonpositive_dt_skipped;
  status_.gaps += later.status_.gaps;
  status_.largest_gap_ns = std::max(status_.largest_gap_ns, later.status_.largest_gap_ns);
  status_.extrapolated_ns += later.status_.extrapolated_ns;
}

void ImuPreintegration::reintegrate(const ImuBias& bias) {
  bias_ = bias;
  reset();
  for (const Step& step : steps_) propagate(step);
}

bool ImuPreintegration::update_bias(const ImuBias& bias) {
  if ((bias.gyro - bias_.gyro).norm() <= options_.reintegrate_gyro_bias_change) return false;
  reintegrate(bias);
  return true;
}

ImuDelta ImuPreintegration::corrected(const Eigen::Vector3d& delta_bg,
                                      const Eigen::Vector3d& delta_ba) const {
  ImuDelta d;
  d.R = delta_.R * so3::exp(dR_dbg_ * delta_bg);
  d.v = delta_.v + dv_dbg_ * delta_bg + dv_dba_ * delta_ba;
  d.p = delta_.p + dp_dbg_ * delta_bg + dp_dba_ * delta_ba;
  return d;
}

ImuDelta ImuPreintegration::corrected(const ImuBias& bias) const {
  return corrected(bias.gyro - bias_.gyro, bias.accel - bias_.accel);
}

Eigen::Matrix<double, 6, 6> ImuPreintegration::bias_random_walk_covariance() const {
  const double T = dt_s();
  Eigen::Matrix<double, 6, 1> d;
  d.head<3>().setConstant(options_.noise.gyro_random_walk * options_.noise.gyro_random_walk * T);
  d.tail<3>().setConstant(options_.noise.accel_random_walk * options_.noise.accel_random_walk * T);
  return d.asDiagonal();
}

namespace {

bool is_finite(const ImuSample& s) {
  return s.gyro.allFinite() && s.accel.allFinite();
}

// Records a stretch of `length_ns` without samples that touches the window.
void note_stretch(ImuIntegrationStatus& status, int64_t length_ns, int64_t max_gap_ns) {
  status.largest_gap_ns = std::max(status.largest_gap_ns, length_ns);
  if (length_ns > max_gap_ns) ++status.gaps;
}

}  // namespace

ImuPreintegration preintegrate(const std::vector<ImuSample>& samples, int64_t t0_ns, int64_t t1_ns,
                               const ImuBias& bias, const ImuOptions& options) {
  if (t1_ns < t0_ns) throw std::invalid_argument("preintegrate: t1_ns < t0_ns");
  ImuPreintegration pim(t0_ns, bias, options);
  ImuIntegrationStatus& status = pim.status_;
  const auto in_window = [&](int64_t t_ns) { return t_ns >= t0_ns && t_ns <= t1_ns; };
  // Holds sample `s` over [from_ns, to_ns] (clipped to the window) where no pair brackets it.
  const auto hold = [&](const ImuSample& s, int64_t from_ns, int64_t to_ns, int64_t stretch_ns) {
    from_ns = std::max(from_ns, t0_ns);
    to_ns = std::min(to_ns, t1_ns);
    if (to_ns <= from_ns) return;
    note_stretch(status, stretch_ns, options.max_gap_ns);
    status.extrapolated_ns += to_ns - from_ns;
    pim.integrate(s.gyro, s.accel, to_ns - from_ns);
  };

  // Skip the samples before the window (bisection, valid for time-ordered buffers and harmless
  // otherwise), keeping the last finite one at or before t0 to interpolate the window start.
  size_t lo = 0, hi = samples.size();
  while (lo < hi) {
    const size_t mid = lo + (hi - lo) / 2;
    if (samples[mid].t_ns <= t0_ns) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  while (lo > 0 && !(is_finite(samples[lo - 1]) && samples[lo - 1].t_ns <= t0_ns)) --lo;
  auto it = samples.begin() + static_cast<std::ptrdiff_t>(lo > 0 ? lo - 1 : 0);

  const ImuSample* prev = nullptr;
  for (; it != samples.end(); ++it) {
    const ImuSample& s = *it;
    if (!is_finite(s)) {
      if (in_window(s.t_ns)) ++status.nonfinite_rejected;
      continue;
    }
    if (prev != nullptr && s.t_ns <= prev->t_ns) {
      if (in_window(s.t_ns)) ++status.nonpositive_dt_skipped;
      continue;
    }
    if (prev == nullptr) {
      hold(s, t0_ns, s.t_ns, s.t_ns - t0_ns);
    } else {
      const int64_t ta = std::max(prev->t_ns, t0_ns);
      const int64_t tb = std::min(s.t_ns, t1_ns);
      if (ta < tb) {
        const int64_t span_ns = s.t_ns - prev->t_ns;
        note_stretch(status, span_ns, options.max_gap_ns);
        // Mean of the linearly interpolated signal over [ta, tb].
        const double f = 0.5 * static_cast<double>((ta - prev->t_ns) + (tb - prev->t_ns)) /
                         static_cast<double>(span_ns);
        pim.integrate(prev->gyro + f * (s.gyro - prev->gyro),
                      prev->accel + f * (s.accel - prev->accel), tb - ta);
      }
    }
    prev = &s;
    if (s.t_ns >= t1_ns) break;
  }
  if (prev == nullptr) {
    if (t1_ns > t0_ns) {  // no data at all is a gap whatever its length
      status.largest_gap_ns = t1_ns - t0_ns;
      ++status.gaps;
    }
  } else {
    hold(*prev, prev->t_ns, t1_ns, t1_ns - prev->t_ns);
  }
  return pim;
}

}  // namespace hs
