// Verification of a place on rendered stereo keyframes (no real data needed): a corner of two
// textured walls and a floor seen from two poses 0.6 m and 25 deg apart gives their relative
// pose; the same viewpoint on walls of another texture is rejected. One texture tile per wall: the
// renderer repeats tiles, and repeated texture is a look-alike place of its own.
#include <gtest/gtest.h>

#include "mapper/place_verify.h"
#include "tests/mapper/place/stereo_keyframe_util.h"
#include "tests/sim/render_test_util.h"

namespace hs {
namespace {

sim::World corner(uint32_t seed) {
  sim::World world;
  const sim::SurfaceStyle style{sim::TextureKind::kMixed, seed, 8.0, 1.0f};
  sim::add_quad(&world, {-4, -1.5, 5}, {8, 0, 0}, {0, 3, 0}, style);  // back wall, z = 5
  sim::add_quad(&world, {4, -1.5, 5}, {0, 0, -8}, {0, 3, 0}, {style.texture, seed + 1, 8.0, 0.8f});
  sim::add_quad(&world, {-4, 1.5, -3}, {8, 0, 0}, {0, 0, 8}, {style.texture, seed + 2, 8.0, 0.9f});
  return world;
}

// The body pose whose cam0 is at T_w_c0.
Eigen::Isometry3d body_for(const StereoCalib& calib, const Eigen::Isometry3d& T_w_c0) {
  return T_w_c0 * calib.cam0.T_b_c.inverse();
}

MapperKeyframe render_keyframe(test::StereoKeyframes& maker, const sim::World& world,
                               const Eigen::Isometry3d& T_w_b, int64_t t_ns) {
  const StereoCalib& calib = maker.calib();
  const sim::RenderOptions options = sim::test::clean_options();
  sim::Renderer r0(world, calib.cam0.intrinsics, options);
  sim::Renderer r1(r0, calib.cam1.intrinsics, options);
  return maker.make(t_ns, r0.render(T_w_b * calib.cam0.T_b_c), r1.render(T_w_b * calib.cam1.T_b_c));
}

TEST(PlaceRendered, TheRelativePoseOfTwoViewsOfOnePlaceIsFound) {
  test::StereoKeyframes maker;
  const sim::World world = corner(3);
  const Eigen::Isometry3d T_w_a = body_for(maker.calib(), Eigen::Isometry3d::Identity());
  Eigen::Isometry3d T_w_c0b = Eigen::Isometry3d::Identity();
  T_w_c0b.translate(Eigen::Vector3d(0.5, 0.1, 0.3));
  T_w_c0b.rotate(Eigen::AngleAxisd(25 * M_PI / 180, Eigen::Vector3d(0.1, 1, 0).normalized()));
  const Eigen::Isometry3d T_w_b = body_for(maker.calib(), T_w_c0b);
  const MapperKeyframe a = render_keyframe(maker, world, T_w_a, 1);
  const MapperKeyframe b = render_keyframe(maker, world, T_w_b, 2);

  const PlaceMatch m = verify_place(b, a, maker.calib(), {});
  ASSERT_TRUE(m.ok) << m.message;
  const Eigen::Isometry3d T_a_b = T_w_a.inverse() * T_w_b;
  EXPECT_LT((m.T_c_q.translation() - T_a_b.translation()).norm(), 0.02) << m.message;
  EXPECT_LT(Eigen::AngleAxisd(m.T_c_q.linear().transpose() * T_a_b.linear()).angle(),
            0.2 * M_PI / 180);
  EXPECT_EQ(m.inlier_keypoints.size(), static_cast<size_t>(m.inliers));
  EXPECT_GE(m.inliers, 50) << m.message;
}

TEST(PlaceRendered, AnotherPlaceSeenFromTheSameViewpointIsRejected) {
  test::StereoKeyframes maker;
  const Eigen::Isometry3d T_w_b = body_for(maker.calib(), Eigen::Isometry3d::Identity());
  const MapperKeyframe a = render_keyframe(maker, corner(3), T_w_b, 1);
  const MapperKeyframe b = render_keyframe(maker, corner(40), T_w_b, 2);
  const PlaceMatch m = verify_place(b, a, maker.calib(), {});
  EXPECT_FALSE(m.ok) << m.message;
}

}  // namespace
}  // namespace hs
