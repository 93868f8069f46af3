#pragma once
// On-manifold IMU preintegration (Forster et al., TRO 2017) between two time stamps, with the
// 9x9 covariance of the deltas, first-order bias correction and re-integration.
//
// Signal model: the IMU signal is the linear interpolation of the samples, so a window
// [t0, t1] integrates exactly the part of the signal inside it, cutting the first and last
// sample intervals. Each step [ta, tb] uses the mean of the signal over the step and a midpoint
// rotation for the velocity/position increments; the bias Jacobians and the covariance are the
// exact linearisation of that discrete scheme.
//
// Error state order everywhere: [rotation (right perturbation), velocity, position].
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "common/core/types.h"
#include "common/imu/imu_options.h"

namespace hs {

using Matrix9d = Eigen::Matrix<double, 9, 9>;
using Vector9d = Eigen::Matrix<double, 9, 1>;

struct ImuBias {
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();   // rad/s
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();  // m/s^2
};

// Preintegrated deltas, expressed in the body frame at the window start.
struct ImuDelta {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
};

// What happened to the samples while building one preintegration. Rejected and skipped samples
// are counted when their time stamp lies inside [t0, t1].
struct ImuIntegrationStatus {
  int nonfinite_rejected = 0;      // NaN/inf gyro or accel
  int nonpositive_dt_skipped = 0;  // time stamp not after the previous accepted sample
  int gaps = 0;                    // stretches without samples longer than max_gap_ns
  int64_t largest_gap_ns = 0;      // longest stretch without samples touching the window
  // Window time before the first or after the last sample, integrated holding that sample.
  int64_t extrapolated_ns = 0;
  bool has_gap() const { return gaps > 0; }
};

class ImuPreintegration {
 public:
  // An empty preintegration starting at t0_ns, linearised at `bias`.
  ImuPreintegration(int64_t t0_ns, const ImuBias& bias, const ImuOptions& options = {});

  // Integrates one step of dt_ns (> 0) with the mean raw measurements over the step. The step
  // noise is the continuous density discretised over the step: sigma_c / sqrt(dt).
  void integrate(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, int64_t dt_ns);
  // Appends the steps of `later` (which must start where this one ends), re-integrated at this
  // linearisation point. Used to merge consecutive preintegrations.
  void append(const ImuPreintegration& later);

  // Re-integrates all steps at a new linearisation point.
  void reintegrate(const ImuBias& bias);
  // Moves the linearisation point to `bias` (re-integrating) when the gyro bias moved further
  // than options.reintegrate_gyro_bias_change; returns whether it did. Otherwise the first-order
  // correction stays in use.
  bool update_bias(const ImuBias& bias);

  // Deltas at the linearisation point, and corrected to first order for bias + (dbg, dba).
  const ImuDelta& delta() const { return delta_; }
  ImuDelta corrected(const Eigen::Vector3d& delta_bg, const Eigen::Vector3d& delta_ba) const;
  ImuDelta corrected(const ImuBias& bias) const;  // relative to bias()

  const ImuBias& bias() const { return bias_; }  // linearisation point
  int64_t t0_ns() const { return t0_ns_; }
  int64_t t1_ns() const { return t1_ns_; }
  double dt_s() const { return ns_to_s(t1_ns_ - t0_ns_); }
  // Covariance of the deltas' noise: [rotation, velocity, position].
  const Matrix9d& covariance() const { return cov_; }
  // Covariance of the bias random walk over the window: [gyro bias, accel bias] (6x6 diag).
  Eigen::Matrix<double, 6, 6> bias_random_walk_covariance() const;

  // Bias Jacobians at the linearisation point.
  const Eigen::Matrix3d& dR_dbg() const { return dR_dbg_; }
  const Eigen::Matrix3d& dv_dbg() const { return dv_dbg_; }
  const Eigen::Matrix3d& dv_dba() const { return dv_dba_; }
  const Eigen::Matrix3d& dp_dbg() const { return dp_dbg_; }
  const Eigen::Matrix3d& dp_dba() const { return dp_dba_; }

  const ImuIntegrationStatus& status() const { return status_; }
  const ImuOptions& options() const { return options_; }

 private:
  friend ImuPreintegration preintegrate(const std::vector<ImuSample>&, int64_t, int64_t,
                                        const ImuBias&, const ImuOptions&);
  struct Step {
    Eigen::Vector3d gyro, accel;  // raw mean measurements
    int64_t dt_ns;
  };
  void reset();
  void propagate(const Step& step);

  ImuOptions options_;
  ImuBias bias_;
  int64_t t0_ns_;
  int64_t t1_ns_;
  std::vector<Step> steps_;
  ImuDelta delta_;
  Matrix9d cov_ = Matrix9d::Zero();
  Eigen::Matrix3d dR_dbg_, dv_dbg_, dv_dba_, dp_dbg_, dp_dba_;
  ImuIntegrationStatus status_;
};

// Preintegrates the signal over [t0_ns, t1_ns] (t1_ns >= t0_ns) from `samples` in time order.
// Samples outside the window only serve to interpolate its ends. Non-finite samples and samples
// not after the previous accepted one are skipped; gaps and uncovered window ends are reported
// in status() and integrated with interpolated / held values, so callers must check it. With
// no usable sample at all the result is empty (t1_ns() == t0_ns) and reported as a gap.
// Throws std::invalid_argument if t1_ns < t0_ns.
ImuPreintegration preintegrate(const std::vector<ImuSample>& samples, int64_t t0_ns, int64_t t1_ns,
                               const ImuBias& bias, const ImuOptions& options = {});

}  // namespace hs
