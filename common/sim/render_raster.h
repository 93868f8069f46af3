#pragma once
// Renderer internals: the quads of a world in one camera pose, binned to tiles, and the
// vectorised nearest-quad (z-buffer) test along rays.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "common/sim/render_rays.h"
#include "common/sim/texture.h"
#include "common/sim/world.h"

namespace hs::sim::detail {

// A quad in one camera pose: 1/z, U/z and V/z (U, V level-0 texel coordinates) are affine in
// the normalised undistorted coordinates (x, y) of a ray, which makes the per-ray work a few
// multiply-adds (perspective-correct interpolation).
struct QuadCoeffs {
  float wa, wb, wc;          // 1/z
  float ua, ub, uc;          // U/z
  float va, vb, vc;          // V/z
  float u_max, v_max;        // the quad is 0 <= U <= u_max, 0 <= V <= v_max
  float u_offset, v_offset;  // texture position of U = V = 0, texels
  float brightness;
  const Texture* texture;
};

struct PoseSetup {
  std::vector<QuadCoeffs> quads;  // per world quad
  // Per tile: 2 * quad index + 1 if the quad covers the whole tile, for the quads whose
  // projection (clipped to z >= near) overlaps the tile.
  std::vector<std::vector<int32_t>> bins;
  float w_near = 0.0f;  // 1 / near distance: rays hit quads only where 1/z < w_near
};

// Fills `setup` for camera pose T_w_c. quad_textures[i] and texture_size: the texture of
// world.quads[i] and its texels per tile side.
void setup_pose(const World& world, const std::vector<const Texture*>& quad_textures,
                int texture_size, const CameraRays& rays, double near_m,
                const Eigen::Isometry3d& T_w_c, PoseSetup* setup);

// z-buffer along n rays (xs, ys) (n a multiple of 4) through tile `tile`: the nearest quad of
// the tile's bin each ray hits (-1: none) and its 1/z (0: none).
void nearest_quads(const PoseSetup& setup, int tile, const float* xs, const float* ys, int n,
                   int32_t* ids, float* best_w);

}  // namespace hs::sim::detail
