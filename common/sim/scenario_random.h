#pragma once
// Portable deterministic random numbers: the same seed gives the same numbers with any standard
// library (std::*_distribution output is implementation-defined), so datasets are reproducible.
#include <cmath>
#include <cstdint>
#include <random>

#include "common/sim/render_rng.h"

namespace hs::sim {

// Independent streams per purpose (IMU noise, world layout, image noise) from one scenario seed.
inline uint64_t stream_seed(uint64_t seed, uint64_t stream) {
  return splitmix64(splitmix64(seed) ^ splitmix64(stream + 0x5EED));
}

// Doubles and normals for the scenario side (render_rng.h's Rng gives 24-bit floats).
class ScenarioRng {
 public:
  explicit ScenarioRng(uint64_t seed) : engine_(seed) {}
  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Standard normal (Box-Muller; both values of a pair are used).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2.0 * M_PI * u2);
    has_spare_ = true;
    return r * std::cos(2.0 * M_PI * u2);
  }

 private:
  std::mt19937_64 engine_;  // fully specified by the standard
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace hs::sim
