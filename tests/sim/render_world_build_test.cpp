// world_build helpers: faces point the documented way and solids bound the geometry.
#include <gtest/gtest.h>

#include "common/sim/world_build.h"

namespace hs::sim {
namespace {

Eigen::Vector3d normal(const TexturedQuad& q) {
  return q.edge_u_w.cross(q.edge_v_w);
}
Eigen::Vector3d centre(const TexturedQuad& q) {
  return q.p0_w + 0.5 * (q.edge_u_w + q.edge_v_w);
}

TEST(RenderWorldBuild, BoxFacesPointOutwards) {
  for (const bool with_bottom : {false, true}) {
    World world;
    Eigen::Isometry3d T_w_box = Eigen::Isometry3d::Identity();
    // Standing boxes (yaw only) drop the face pointing down; any orientation otherwise.
    const Eigen::Vector3d axis =
        with_bottom ? Eigen::Vector3d(1, 2, 3).normalized() : Eigen::Vector3d::UnitZ();
    T_w_box.linear() = Eigen::AngleAxisd(0.7, axis).matrix();
    T_w_box.translation() = Eigen::Vector3d(1, -2, 0.5);
    const Eigen::Vector3d half(0.3, 0.5, 0.7);
    add_box(&world, T_w_box, half, {TextureKind::kBrick, 40, 1.0, 1.0f}, with_bottom);
    ASSERT_EQ(world.quads.size(), with_bottom ? 6u : 5u);
    ASSERT_EQ(world.solids.size(), 1u);
    double area = 0.0;
    for (size_t i = 0; i < world.quads.size(); ++i) {
      const TexturedQuad& q = world.quads[i];
      const Eigen::Vector3d out = centre(q) - T_w_box.translation();
      EXPECT_GT(normal(q).dot(out), 0.0);
      EXPECT_GT(normal(q).normalized().z(), with_bottom ? -1.01 : -0.5);
      // The face centre lies on the box surface.
      const Eigen::Vector3d local = (T_w_box.inverse() * centre(q)).cwiseAbs();
      EXPECT_NEAR((local - half).cwiseAbs().minCoeff(), 0.0, 1e-12);
      EXPECT_EQ(q.texture_seed, 40u);
      for (size_t j = 0; j < i; ++j) {  // faces show different parts of the shared texture
        EXPECT_GT((world.quads[j].texture_offset - q.texture_offset).norm(), 0.05);
      }
      area += normal(q).norm();
    }
    const double full = 8 * (half.x() * half.y() + half.y() * half.z() + half.x() * half.z());
    const double bottom = 4 * half.x() * half.y();
    EXPECT_NEAR(area, with_bottom ? full : full - bottom, 1e-9);
  }
}

TEST(RenderWorldBuild, RoomFacesPointInwardsAndSlabsEncloseIt) {
  World world;
  const Eigen::Vector3d lo(-4, -3, 0), hi(4, 3, 2.5);
  add_room(&world, lo, hi, {TextureKind::kMixed, 1, 2.0, 1.0f},
           {TextureKind::kGravel, 10, 2.0, 1.0f}, {TextureKind::kPlain, 20, 3.0, 1.0f});
  ASSERT_EQ(world.quads.size(), 6u);
  const Eigen::Vector3d mid = 0.5 * (lo + hi);
  for (const TexturedQuad& q : world.quads) {
    EXPECT_LT(normal(q).dot(centre(q) - mid), 0.0);
  }
  EXPECT_EQ(world.quads[0].texture, TextureKind::kGravel);  // floor
  EXPECT_NEAR(normal(world.quads[0]).normalized().z(), 1.0, 1e-12);
  // Walls are upright with a horizontal edge_u (so brick courses stay level).
  for (size_t i = 2; i < 6; ++i) {
    EXPECT_EQ(world.quads[i].edge_u_w.z(), 0.0);
    EXPECT_GT(world.quads[i].edge_v_w.z(), 0.0);
  }
  // Six slabs, each just outside one face.
  ASSERT_EQ(world.solids.size(), 6u);
  for (const SolidBox& s : world.solids) {
    const Eigen::Vector3d c = s.T_w_box.translation();
    const Eigen::Vector3d inner = (c - mid).cwiseAbs() - s.half_size;
    EXPECT_NEAR((inner - 0.5 * (hi - lo)).maxCoeff(), 0.0, 1e-12);
  }
}

}  // namespace
}  // namespace hs::sim
