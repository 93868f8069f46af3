#pragma once
// Renderer internals: per-camera ray tables. The image is cut into 16x16 pixel tiles; for each
// tile, the normalised undistorted ray (x, y) of every pixel corner and pixel centre is stored
// contiguously (tile-major), so the per-tile loops read them as plain vectors.
#include <vector>

#include "common/calib/pinhole_radtan.h"

namespace hs::sim::detail {

constexpr int kTile = 16;                   // tile side, pixels
constexpr int kGrid = kTile + 1;            // pixel-corner grid side of a tile
constexpr int kGridPad = 292;               // kGrid^2 = 289 rounded up to whole vectors
constexpr int kTilePixels = kTile * kTile;  // pixel centres per tile

struct CameraRays {
  explicit CameraRays(const PinholeRadtan& camera);

  int tiles() const { return tiles_x * tiles_y; }
  int tile_u0(int tile) const { return (tile % tiles_x) * kTile; }  // first pixel column
  int tile_v0(int tile) const { return (tile / tiles_x) * kTile; }  // first pixel row
  const float* corner_xs(int tile) const { return &corner_x[static_cast<size_t>(tile) * kGridPad]; }
  const float* corner_ys(int tile) const { return &corner_y[static_cast<size_t>(tile) * kGridPad]; }

  int width, height, tiles_x, tiles_y;
  // Pixel corners (u - 0.5, v - 0.5), kGrid x kGrid row-major per tile, padded to kGridPad.
  std::vector<float> corner_x, corner_y;
  // Pixel centres, kTile x kTile row-major per tile, and the pixel footprint scale: largest
  // singular value of d(x, y)/d(u, v), for mip selection.
  std::vector<float> centre_x, centre_y, pixel_scale;
  // Per tile: x min, x max, y min, y max of its corner rays (with a small margin): every ray
  // through the tile lies inside.
  std::vector<float> tile_box;
};

}  // namespace hs::sim::detail
