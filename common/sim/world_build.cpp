#include "common/sim/world_build.h"

#include <cmath>

namespace hs::sim {
namespace {

// Fixed "light from above" so faces of different orientation differ in brightness.
float face_shade(const Eigen::Vector3d& n_w) {
  return static_cast<float>(0.8 + 0.2 * n_w.z() + 0.1 * n_w.x());
}

// Texture offset (tiles) of the i-th face sharing a texture: irrational steps, so faces
// show unrelated parts of the tile.
Eigen::Vector2d face_offset(int i) {
  return {std::fmod(0.618034 * i, 1.0), std::fmod(0.414214 * i, 1.0)};
}

void add_face(World* world, const Eigen::Vector3d& p0_w, const Eigen::Vector3d& edge_u_w,
              const Eigen::Vector3d& edge_v_w, const SurfaceStyle& style, int face) {
  add_quad(world, p0_w, edge_u_w, edge_v_w, style);
  world->quads.back().texture_offset = face_offset(face);
}

}  // namespace

void add_quad(World* world, const Eigen::Vector3d& p0_w, const Eigen::Vector3d& edge_u_w,
              const Eigen::Vector3d& edge_v_w, const SurfaceStyle& style) {
  TexturedQuad q;
  q.p0_w = p0_w;
  q.edge_u_w = edge_u_w;
  q.edge_v_w = edge_v_w;
  q.texture = style.texture;
  q.texture_seed = style.seed;
  q.metres_per_tile = style.metres_per_tile;
  q.brightness = style.brightness;
  world->quads.push_back(q);
}

void add_box(World* world, const Eigen::Isometry3d& T_w_box, const Eigen::Vector3d& half_size,
             const SurfaceStyle& style, bool with_bottom) {
  const Eigen::Matrix3d R = T_w_box.linear();
  int face = 0;
  for (int a = 0; a < 3; ++a) {
    // (a, b, c) cyclic, so e_b x e_c = e_a.
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const Eigen::Vector3d ea = R.col(a) * half_size[a], eb = R.col(b) * half_size[b],
                          ec = R.col(c) * half_size[c];
    for (const double sign : {1.0, -1.0}) {
      const Eigen::Vector3d n_w = sign * R.col(a);
      if (!with_bottom && n_w.z() < -0.99) continue;
      SurfaceStyle s = style;
      s.brightness *= face_shade(n_w);
      const Eigen::Vector3d p0 = T_w_box.translation() + sign * ea - eb - ec;
      if (sign > 0) {
        add_face(world, p0, 2.0 * eb, 2.0 * ec, s, face++);
      } else {
        add_face(world, p0, 2.0 * ec, 2.0 * eb, s, face++);
      }
    }
  }
  world->solids.push_back({T_w_box, half_size});
}

void add_room(World* world, const Eigen::Vector3d& min_w, const Eigen::Vector3d& max_w,
              const SurfaceStyle& walls, const SurfaceStyle& floor, const SurfaceStyle& ceiling) {
  const Eigen::Vector3d d = max_w - min_w;
  const Eigen::Vector3d dx(d.x(), 0, 0), dy(0, d.y(), 0), dz(0, 0, d.z());
  const Eigen::Vector3d lo = min_w, hi = max_w;
  add_quad(world, lo, dx, dy, floor);
  add_quad(world, {lo.x(), lo.y(), hi.z()}, dy, dx, ceiling);
  // Walls: edge_u horizontal, edge_v up, facing inwards.
  add_face(world, lo, dy, dz, walls, 0);
  add_face(world, {hi.x(), hi.y(), lo.z()}, -dy, dz, walls, 1);
  add_face(world, {hi.x(), lo.y(), lo.z()}, -dx, dz, walls, 2);
  add_face(world, {lo.x(), hi.y(), lo.z()}, dx, dz, walls, 3);

  constexpr double kSlab = 0.2;
  const Eigen::Vector3d mid = 0.5 * (lo + hi), half = 0.5 * d + Eigen::Vector3d::Constant(kSlab);
  for (int a = 0; a < 3; ++a) {
    for (const double sign : {-1.0, 1.0}) {
      SolidBox slab;
      slab.half_size = half;
      slab.half_size[a] = 0.5 * kSlab;
      Eigen::Vector3d centre = mid;
      centre[a] += sign * (0.5 * d[a] + 0.5 * kSlab);
      slab.T_w_box.translation() = centre;
      world->solids.push_back(slab);
    }
  }
}

}  // namespace hs::sim
