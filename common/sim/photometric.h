#pragma once
// Sensor effects applied to a radiance image: exposure/gain, vignetting, read + shot noise and
// 8-bit quantisation, in one vectorised pass.
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "common/calib/pinhole_radtan.h"

namespace hs::sim {

struct PhotometricOptions {
  bool noise = true;
  float read_noise_dn = 1.5f;     // Gaussian read noise sigma, grey levels
  float shot_noise_gain = 0.05f;  // shot noise variance per grey level (sigma^2 = gain * I)
  bool vignetting = true;
  // 0 = none, 1 = full cos^4 of the angle of the (distorted) pinhole ray through the pixel;
  // the factor is 1 - s * (1 - cos^4).
  float vignetting_strength = 0.3f;
};

class Photometric {
 public:
  Photometric(const PinholeRadtan& camera, const PhotometricOptions& options);

  // radiance: width*height floats (0..255 scale), row-major; used as scratch (overwritten).
  // Writes a CV_8UC1 image: round(radiance * gain * vignetting + noise), saturated.
  // Deterministic given noise_seed.
  void apply(float* radiance, double gain, uint64_t noise_seed, cv::Mat* image) const;

  // Vignetting factor of pixel (u, v) (1 when vignetting is off).
  float vignetting(int u, int v) const;

 private:
  PhotometricOptions options_;
  int width_, height_;
  float inv_fx_, inv_fy_, cx_, cy_;
  // Standard normal samples; each row reads a contiguous run at a seeded random offset, so
  // noise costs one load per pixel.
  std::vector<float> noise_;
};

}  // namespace hs::sim
