#pragma once
// The simulated world: textured planar quads (walls, floors, box faces) that the renderer draws,
// plus solid volumes that scenario validation checks trajectories against.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace hs::sim {

// Procedural texture families. kPlain is (nearly) textureless, for the hard-case scenario.
enum class TextureKind { kMixed, kBrick, kBlobs, kGravel, kPlain };

struct TexturedQuad {
  Eigen::Vector3d p0_w = Eigen::Vector3d::Zero();       // a corner
  Eigen::Vector3d edge_u_w = Eigen::Vector3d::UnitX();  // corners: p0 + s*edge_u + t*edge_v,
  Eigen::Vector3d edge_v_w = Eigen::Vector3d::UnitY();  // s, t in [0, 1]
  TextureKind texture = TextureKind::kMixed;
  uint32_t texture_seed = 0;
  double metres_per_tile = 1.0;  // world size of one texture tile
  float brightness = 1.0f;       // albedo scale
  // Texture position of corner p0, in tiles: faces sharing a texture show different parts.
  Eigen::Vector2d texture_offset = Eigen::Vector2d::Zero();
};

// An oriented box volume (half sizes along the box axes).
struct SolidBox {
  Eigen::Isometry3d T_w_box = Eigen::Isometry3d::Identity();
  Eigen::Vector3d half_size = Eigen::Vector3d::Ones();
};

struct World {
  std::vector<TexturedQuad> quads;
  std::vector<SolidBox> solids;
};

}  // namespace hs::sim
