#include "common/sim/render_raster.h"

#include <algorithm>
#include <cmath>

#include "common/sim/render_simd.h"

namespace hs::sim::detail {

using simd::v4f;
using simd::v4i;

void setup_pose(const World& world, const std::vector<const Texture*>& quad_textures,
                int texture_size, const CameraRays& rays, double near_m,
                const Eigen::Isometry3d& T_w_c, PoseSetup* setup) {
  const Eigen::Isometry3d T_c_w = T_w_c.inverse();
  setup->quads.resize(world.quads.size());
  setup->bins.resize(static_cast<size_t>(rays.tiles()));
  for (auto& bin : setup->bins) bin.clear();
  setup->w_near = static_cast<float>(1.0 / near_m);
  std::vector<Eigen::Vector2d> poly;
  for (size_t qi = 0; qi < world.quads.size(); ++qi) {
    const TexturedQuad& quad = world.quads[qi];
    const Eigen::Vector3d p0 = T_c_w * quad.p0_w;
    const Eigen::Vector3d eu = T_c_w.linear() * quad.edge_u_w;
    const Eigen::Vector3d ev = T_c_w.linear() * quad.edge_v_w;
    const Eigen::Vector3d n = eu.cross(ev);
    const double n2 = n.squaredNorm(), d = n.dot(p0);
    if (n2 < 1e-18 || std::abs(d) < 1e-9 * std::sqrt(n2)) continue;  // degenerate or edge-on
    // Ray p = z (x, y, 1): 1/z = n.(x, y, 1) / d. With dual vectors a_s.eu = 1, a_s.ev = 0,
    // a_s.n = 0: s = a_s.(p - p0), so s/z = a_s.(x, y, 1) - (a_s.p0) / z.
    const Eigen::Vector3d w = n / d;
    const Eigen::Vector3d a_s = ev.cross(n) / n2, a_t = n.cross(eu) / n2;
    const double texels = texture_size / quad.metres_per_tile;
    const double u_max = quad.edge_u_w.norm() * texels, v_max = quad.edge_v_w.norm() * texels;
    const Eigen::Vector3d u = (a_s - a_s.dot(p0) * w) * u_max;
    const Eigen::Vector3d v = (a_t - a_t.dot(p0) * w) * v_max;
    setup->quads[qi] = {static_cast<float>(w.x()),
                        static_cast<float>(w.y()),
                        static_cast<float>(w.z()),
                        static_cast<float>(u.x()),
                        static_cast<float>(u.y()),
                        static_cast<float>(u.z()),
                        static_cast<float>(v.x()),
                        static_cast<float>(v.y()),
                        static_cast<float>(v.z()),
                        static_cast<float>(u_max),
                        static_cast<float>(v_max),
                        static_cast<float>(quad.texture_offset.x() * texture_size),
                        static_cast<float>(quad.texture_offset.y() * texture_size),
                        quad.brightness,
                        quad_textures[qi]};

    // Clip the quad to z >= near (Sutherland-Hodgman) and project it for binning.
    const Eigen::Vector3d corners[4] = {p0, p0 + eu, p0 + eu + ev, p0 + ev};
    poly.clear();
    for (int i = 0; i < 4; ++i) {
      const Eigen::Vector3d& a = corners[i];
      const Eigen::Vector3d& b = corners[(i + 1) % 4];
      if (a.z() >= near_m) poly.push_back(a.head<2>() / a.z());
      if ((a.z() >= near_m) != (b.z() >= near_m)) {
        const Eigen::Vector3d m = a + (b - a) * ((near_m - a.z()) / (b.z() - a.z()));
        poly.push_back(m.head<2>() / near_m);
      }
    }
    if (poly.size() < 3) continue;
    Eigen::Vector2d lo = poly[0], hi = poly[0];
    double area2 = 0.0;
    for (size_t i = 0; i < poly.size(); ++i) {
      lo = lo.cwiseMin(poly[i]);
      hi = hi.cwiseMax(poly[i]);
      const Eigen::Vector2d& b = poly[(i + 1) % poly.size()];
      area2 += poly[i].x() * b.y() - poly[i].y() * b.x();
    }
    const double orient = area2 >= 0.0 ? 1.0 : -1.0;
    for (int t = 0; t < rays.tiles(); ++t) {
      const float* box = &rays.tile_box[static_cast<size_t>(t) * 4];
      if (hi.x() < box[0] || lo.x() > box[1] || hi.y() < box[2] || lo.y() > box[3]) continue;
      // Separating axis: a polygon edge with all four box corners outside it. With no corner
      // outside any edge the quad covers the whole tile, which needs only the depth test.
      int worst = 0;  // most box corners outside one edge
      for (size_t i = 0; i < poly.size() && worst < 4; ++i) {
        const Eigen::Vector2d& a = poly[i];
        const Eigen::Vector2d e = poly[(i + 1) % poly.size()] - a;
        int outside = 0;
        for (int k = 0; k < 4; ++k) {
          const double bx = box[k & 1], by = box[2 + (k >> 1)];
          outside += orient * (e.x() * (by - a.y()) - e.y() * (bx - a.x())) < 0.0;
        }
        worst = std::max(worst, outside);
      }
      if (worst < 4) {
        setup->bins[static_cast<size_t>(t)].push_back(static_cast<int32_t>(qi) * 2 + (worst == 0));
      }
    }
  }
}

void nearest_quads(const PoseSetup& setup, int tile, const float* xs, const float* ys, int n,
                   int32_t* ids, float* best_w) {
  std::fill(ids, ids + n, -1);
  std::fill(best_w, best_w + n, 0.0f);  // w must beat 0: in front of the camera
  const v4f w_near = v4f{} + setup.w_near;
  const v4f zero = v4f{};
  for (const int32_t entry : setup.bins[static_cast<size_t>(tile)]) {
    const int32_t qi = entry >> 1;
    const QuadCoeffs& q = setup.quads[static_cast<size_t>(qi)];
    const v4i id = v4i{} + qi;
    if (entry & 1) {  // covers the tile: every ray hits it, in front of the near plane
      for (int i = 0; i < n; i += 4) {
        const v4f w = q.wa * simd::load(xs + i) + q.wb * simd::load(ys + i) + q.wc;
        const v4f bw = simd::load(best_w + i);
        const v4i hit = w > bw;
        simd::store(best_w + i, hit ? w : bw);
        simd::store(ids + i, hit ? id : simd::load(ids + i));
      }
      continue;
    }
    for (int i = 0; i < n; i += 4) {
      const v4f x = simd::load(xs + i), y = simd::load(ys + i);
      const v4f w = q.wa * x + q.wb * y + q.wc;
      const v4f u = q.ua * x + q.ub * y + q.uc;
      const v4f v = q.va * x + q.vb * y + q.vc;
      const v4f bw = simd::load(best_w + i);
      const v4i hit = (w > bw) & (w < w_near) & (u >= zero) & (u <= q.u_max * w) & (v >= zero) &
                      (v <= q.v_max * w);
      simd::store(best_w + i, hit ? w : bw);
      simd::store(ids + i, hit ? id : simd::load(ids + i));
    }
  }
}

}  // namespace hs::sim::detail
