#pragma once
// Small scenes for the renderer tests. The camera sits at the world origin looking along +z
// (T_w_c = identity), so world and camera coordinates coincide.
#include <Eigen/Geometry>

#include "common/calib/camera_calib.h"
#include "common/sim/render.h"
#include "common/sim/world_build.h"

namespace hs::sim::test {

// A square facing the camera (normal along -z), centred at `centre`.
inline void add_facing_square(World* world, const Eigen::Vector3d& centre, double half,
                              const SurfaceStyle& style) {
  add_quad(world, centre - Eigen::Vector3d(half, half, 0), Eigen::Vector3d(2 * half, 0, 0),
           Eigen::Vector3d(0, 2 * half, 0), style);
}

// A uniform (kPlain) surface of brightness b: radiance ~153 * b.
inline SurfaceStyle plain(float brightness, uint32_t seed = 1) {
  return {TextureKind::kPlain, seed, 10.0, brightness};
}

// Noise, vignetting and blur off; small textures so tests (and sanitizer builds) stay fast.
inline RenderOptions clean_options() {
  RenderOptions o;
  o.photometric.noise = false;
  o.photometric.vignetting = false;
  o.motion_blur = false;
  o.texture_size = 256;
  return o;
}

inline PinholeRadtan euroc_cam0() {
  return euroc_stereo_calib().cam0.intrinsics;
}

}  // namespace hs::sim::test
