#include "common/sim/render_rays.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace hs::sim::detail {

CameraRays::CameraRays(const PinholeRadtan& cam)
    : width(cam.width),
      height(cam.height),
      tiles_x((cam.width + kTile - 1) / kTile),
      tiles_y((cam.height + kTile - 1) / kTile) {
  corner_x.resize(static_cast<size_t>(tiles()) * kGridPad);
  corner_y.resize(corner_x.size());
  centre_x.resize(static_cast<size_t>(tiles()) * kTilePixels);
  centre_y.resize(centre_x.size());
  pixel_scale.resize(centre_x.size());
  tile_box.resize(static_cast<size_t>(tiles()) * 4);
  const Eigen::Vector2d f(cam.fx, cam.fy);
  for (int t = 0; t < tiles(); ++t) {
    const int u0 = tile_u0(t), v0 = tile_v0(t);
    float* cx = &corner_x[static_cast<size_t>(t) * kGridPad];
    float* cy = &corner_y[static_cast<size_t>(t) * kGridPad];
    float* box = &tile_box[static_cast<size_t>(t) * 4];
    box[0] = box[2] = std::numeric_limits<float>::max();
    box[1] = box[3] = std::numeric_limits<float>::lowest();
    for (int i = 0; i < kGridPad; ++i) {
      const int g = std::min(i, kGrid * kGrid - 1);  // padding repeats the last corner
      const Eigen::Vector2d xy =
          cam.unproject_normalised({u0 + g % kGrid - 0.5, v0 + g / kGrid - 0.5});
      cx[i] = static_cast<float>(xy.x());
      cy[i] = static_cast<float>(xy.y());
      box[0] = std::min(box[0], cx[i]);
      box[1] = std::max(box[1], cx[i]);
      box[2] = std::min(box[2], cy[i]);
      box[3] = std::max(box[3], cy[i]);
    }
    // Tile borders are slightly curved between corners; a small margin keeps binning safe.
    const float mx = 0.02f * (box[1] - box[0]), my = 0.02f * (box[3] - box[2]);
    box[0] -= mx;
    box[1] += mx;
    box[2] -= my;
    box[3] += my;
    for (int i = 0; i < kTilePixels; ++i) {
      const Eigen::Vector2d xy = cam.unproject_normalised({u0 + i % kTile, v0 + i / kTile});
      const size_t k = static_cast<size_t>(t) * kTilePixels + i;
      centre_x[k] = static_cast<float>(xy.x());
      centre_y[k] = static_cast<float>(xy.y());
      // d(x, y)/d(u, v) = J^-1 with J = (distortion Jacobian) diag(fx, fy): its largest
      // singular value is 1 / (smallest singular value of J).
      const Eigen::Matrix2d J = cam.distort_jacobian(xy) * f.asDiagonal();
      const double det = J.determinant(), frob2 = J.squaredNorm();
      const double s_min2 = 0.5 * (frob2 - std::sqrt(std::max(0.0, frob2 * frob2 - 4 * det * det)));
      pixel_scale[k] = static_cast<float>(1.0 / std::sqrt(s_min2));
    }
  }
}

}  // namespace hs::sim::detail
