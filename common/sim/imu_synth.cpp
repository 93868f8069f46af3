#include "common/sim/imu_synth.h"

#include <cmath>
#include <stdexcept>

#include "common/sim/scenario_random.h"

namespace hs::sim {
namespace {

Eigen::Vector3d normal3(ScenarioRng& rng) {
  const double x = rng.normal(), y = rng.normal(), z = rng.normal();
  return {x, y, z};
}

bool in_gap(const std::vector<TimeWindow>& gaps, int64_t t_ns) {
  for (const TimeWindow& g : gaps)
    if (t_ns > g.start_ns && t_ns < g.end_ns) return true;
  return false;
}

}  // namespace

int64_t imu_period_ns(double rate_hz) {
  if (!(rate_hz > 0.0)) throw std::invalid_argument("imu_period_ns: rate must be positive");
  return std::llround(kNsPerSec / rate_hz);
}

ImuSample ideal_imu(const BodyKinematics& k, int64_t t_ns) {
  ImuSample s;
  s.t_ns = t_ns;
  s.gyro = k.omega_b;
  s.accel = k.q_w_b.conjugate() * (k.a_w + Eigen::Vector3d(0, 0, kGravityMps2));
  return s;
}

ImuSeries synthesize_imu(const Trajectory& trajectory, const ImuSynthOptions& options,
                         int64_t t0_ns, int64_t t_end_ns, uint64_t seed) {
  const int64_t period_ns = imu_period_ns(options.rate_hz);
  const double dt = ns_to_s(period_ns);
  const double gyro_sigma = options.gyro_noise_density / std::sqrt(dt);
  const double accel_sigma = options.accel_noise_density / std::sqrt(dt);
  const double gyro_walk = options.gyro_random_walk * std::sqrt(dt);
  const double accel_walk = options.accel_random_walk * std::sqrt(dt);

  ScenarioRng rng(seed);
  Eigen::Vector3d bg = options.gyro_bias, ba = options.accel_bias;
  ImuSeries out;
  for (int64_t t_ns = t0_ns; t_ns <= t_end_ns; t_ns += period_ns) {
    const BodyKinematics k = trajectory.at(ns_to_s(t_ns - t0_ns));
    NavState truth;
    truth.t_ns = t_ns;
    truth.p_w_b = k.p_w_b;
    truth.q_w_b = k.q_w_b;
    truth.v_w = k.v_w;
    truth.gyro_bias = bg;
    truth.accel_bias = ba;
    out.truth.push_back(truth);

    // Noise is drawn for every sample, gaps included, so a gap does not shift later noise.
    ImuSample s = ideal_imu(k, t_ns);
    s.gyro += bg + gyro_sigma * normal3(rng);
    s.accel += ba + accel_sigma * normal3(rng);
    if (!in_gap(options.gaps, t_ns - t0_ns)) out.samples.push_back(s);
    bg += gyro_walk * normal3(rng);
    ba += accel_walk * normal3(rng);
  }
  return out;
}

}  // namespace hs::sim
