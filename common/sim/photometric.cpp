#include "common/sim/photometric.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/sim/render_rng.h"
#include "common/sim/render_simd.h"

namespace hs::sim {
namespace {

// Noise table size: large enough that rows rarely share samples.
constexpr int kNoiseTableBits = 18;

}  // namespace

Photometric::Photometric(const PinholeRadtan& camera, const PhotometricOptions& options)
    : options_(options),
      width_(camera.width),
      height_(camera.height),
      inv_fx_(static_cast<float>(1.0 / camera.fx)),
      inv_fy_(static_cast<float>(1.0 / camera.fy)),
      cx_(static_cast<float>(camera.cx)),
      cy_(static_cast<float>(camera.cy)) {
  Rng rng(0x0A15E);
  noise_.resize((size_t{1} << kNoiseTableBits) + width_ + 4);          // whole vectors past the end
  for (size_t i = 0; i + 1 < noise_.size(); i += 2) {                  // Box-Muller pairs
    const double r = std::sqrt(-2.0 * std::log(1.0 - rng.uniform()));  // 1 - u avoids log(0)
    const double a = 6.283185307179586 * rng.uniform();
    noise_[i] = static_cast<float>(r * std::cos(a));
    noise_[i + 1] = static_cast<float>(r * std::sin(a));
  }
}

float Photometric::vignetting(int u, int v) const {
  const float dx = (static_cast<float>(u) - cx_) * inv_fx_;
  const float dy = (static_cast<float>(v) - cy_) * inv_fy_;
  const float strength = options_.vignetting ? options_.vignetting_strength : 0.0f;
  const float cos2 = 1.0f / (1.0f + dx * dx + dy * dy);
  return 1.0f - strength + strength * cos2 * cos2;
}

void Photometric::apply(float* radiance, double gain, uint64_t noise_seed, cv::Mat* image) const {
  using simd::v4f;
  const float g = static_cast<float>(gain);
  const float read2 = options_.read_noise_dn * options_.read_noise_dn;
  const float shot = options_.shot_noise_gain;
  const float strength = options_.vignetting ? options_.vignetting_strength : 0.0f;
  const v4f lane = {0.0f, 1.0f, 2.0f, 3.0f};
  const uint64_t mask = (uint64_t{1} << kNoiseTableBits) - 1;
  for (int v = 0; v < height_; ++v) {
    float* row = radiance + static_cast<size_t>(v) * width_;
    const float* noise =
        options_.noise ? noise_.data() + (splitmix64(noise_seed * 1000003u + v) & mask) : nullptr;
    const float dy = (static_cast<float>(v) - cy_) * inv_fy_;
    const float r2_row = 1.0f + dy * dy;
    // Pixels u .. u + 3 at p (whole vectors; the row's last partial vector goes via `tail`).
    const auto apply4 = [&](int u, float* p) {
      const v4f dx = (static_cast<float>(u) + lane - cx_) * inv_fx_;
      const v4f cos2 = 1.0f / (r2_row + dx * dx);  // same formula as vignetting()
      const v4f i = simd::load(p) * (g * (1.0f - strength + strength * cos2 * cos2));
      if (noise == nullptr) {
        simd::store(p, i);
        return;
      }
      const v4f clipped = simd::max(i, v4f{});
      simd::store(p, clipped + simd::sqrt(read2 + shot * clipped) * simd::load(noise + u));
    };
    int u = 0;
    for (; u + 4 <= width_; u += 4) apply4(u, row + u);
    if (u < width_) {
      alignas(16) float tail[4] = {};
      std::copy(row + u, row + width_, tail);
      apply4(u, tail);
      std::copy(tail, tail + (width_ - u), row + u);
    }
  }
  // Rounds and saturates (OpenCV's conversion is vectorised for the CPU at run time).
  cv::Mat(height_, width_, CV_32FC1, radiance).convertTo(*image, CV_8U);
}

}  // namespace hs::sim
