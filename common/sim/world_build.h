#pragma once
// Helpers that add common structures to a World. Quads are drawn two-sided; the helpers still
// orient edge_u x edge_v towards the visible side. The faces of one box (or the walls of one
// room) share the style's texture but show different parts of it (texture_offset), so they
// differ without costing a texture each.
#include <Eigen/Geometry>
#include <cstdint>

#include "common/sim/world.h"

namespace hs::sim {

struct SurfaceStyle {
  TextureKind texture = TextureKind::kMixed;
  uint32_t seed = 0;
  double metres_per_tile = 2.0;
  float brightness = 1.0f;
};

// One quad with corner p0 and edges edge_u, edge_v.
void add_quad(World* world, const Eigen::Vector3d& p0_w, const Eigen::Vector3d& edge_u_w,
              const Eigen::Vector3d& edge_v_w, const SurfaceStyle& style);

// A box: its 6 outward faces (without the face pointing down, if any, when `with_bottom` is
// false: boxes standing on a floor) and a SolidBox. Faces get slightly different brightness, as
// from a light above, so box edges are visible.
void add_box(World* world, const Eigen::Isometry3d& T_w_box, const Eigen::Vector3d& half_size,
             const SurfaceStyle& style, bool with_bottom = false);

// A closed room [min_w, max_w] (axis aligned, z up): floor, ceiling and 4 walls facing inwards,
// plus 0.2 m thick SolidBox slabs outside each face so trajectory checks against solids also
// keep paths inside the room. Floor uses `floor`, ceiling `ceiling`, walls `walls`.
void add_room(World* world, const Eigen::Vector3d& min_w, const Eigen::Vector3d& max_w,
              const SurfaceStyle& walls, const SurfaceStyle& floor, const SurfaceStyle& ceiling);

}  // namespace hs::sim
