#include "common/calib/pinhole_radtan.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "common/calib/camera_calib.h"

namespace hs {
namespace {

PinholeRadtan cam0() {
  return euroc_stereo_calib().cam0.intrinsics;
}

TEST(PinholeRadtan, UnprojectProjectRoundTripOverWholeImage) {
  for (const PinholeRadtan& cam :
       {euroc_stereo_calib().cam0.intrinsics, euroc_stereo_calib().cam1.intrinsics}) {
    double worst = 0.0;
    // Every 4th pixel plus the extreme image corners (pixel edges at -0.5 and size - 0.5).
    for (double v = -0.5; v <= cam.height - 0.5; v += (v < 0 ? 0.5 : 4.0)) {
      for (double u = -0.5; u <= cam.width - 0.5; u += (u < 0 ? 0.5 : 4.0)) {
        const Eigen::Vector2d uv(u, v);
        const Eigen::Vector3d bearing = cam.unproject(uv);
        EXPECT_NEAR(bearing.norm(), 1.0, 1e-12);
        worst = std::max(worst, (cam.project(bearing * 3.7) - uv).norm());
      }
    }
    for (const Eigen::Vector2d& corner :
         {Eigen::Vector2d(-0.5, -0.5), Eigen::Vector2d(cam.width - 0.5, -0.5),
          Eigen::Vector2d(-0.5, cam.height - 0.5),
          Eigen::Vector2d(cam.width - 0.5, cam.height - 0.5)}) {
      worst = std::max(worst, (cam.project(cam.unproject(corner)) - corner).norm());
    }
    EXPECT_LT(worst, 1e-6);
  }
}

TEST(PinholeRadtan, ProjectUnprojectRoundTrip) {
  const PinholeRadtan cam = cam0();
  for (double x = -1.0; x <= 1.0; x += 0.1) {
    for (double y = -0.6; y <= 0.6; y += 0.1) {
      const Eigen::Vector3d p_c(x * 2.0, y * 2.0, 2.0);
      const Eigen::Vector3d back = cam.unproject(cam.project(p_c));
      EXPECT_LT((back - p_c.normalized()).norm(), 1e-9) << x << " " << y;
    }
  }
}

TEST(PinholeRadtan, JacobianMatchesNumericalDerivative) {
  const PinholeRadtan cam = cam0();
  const double h = 1e-6;
  for (const Eigen::Vector3d& p_c :
       {Eigen::Vector3d(0.1, -0.2, 1.5), Eigen::Vector3d(-1.2, 0.7, 2.0),
        Eigen::Vector3d(0.9, 0.5, 1.1), Eigen::Vector3d(0.0, 0.0, 0.5)}) {
    Eigen::Vector2d uv;
    Eigen::Matrix<double, 2, 3> J;
    ASSERT_TRUE(cam.project(p_c, &uv, &J)) << p_c.transpose();
    Eigen::Matrix<double, 2, 3> numeric;
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d d = Eigen::Vector3d::Unit(i) * h;
      numeric.col(i) = (cam.project(p_c + d) - cam.project(p_c - d)) / (2 * h);
    }
    EXPECT_LT((J - numeric).norm(), 1e-6 * J.norm()) << "\n" << J << "\n" << numeric;
  }
}

TEST(PinholeRadtan, DistortJacobianMatchesNumericalDerivative) {
  PinholeRadtan cam = cam0();
  cam.p1 = 0.002;  // make the tangential terms matter
  cam.p2 = -0.003;
  const Eigen::Vector2d xy(0.4, -0.3);
  const double h = 1e-7;
  Eigen::Matrix2d numeric;
  for (int i = 0; i < 2; ++i) {
    const Eigen::Vector2d d = Eigen::Vector2d::Unit(i) * h;
    numeric.col(i) = (cam.distort(xy + d) - cam.distort(xy - d)) / (2 * h);
  }
  EXPECT_LT((cam.distort_jacobian(xy) - numeric).norm(), 1e-7);
}

TEST(PinholeRadtan, ValidityFlag) {
  const PinholeRadtan cam = cam0();
  Eigen::Vector2d uv;
  EXPECT_TRUE(cam.project(Eigen::Vector3d(0.0, 0.0, 1.0), &uv));
  EXPECT_NEAR(uv.x(), cam.cx, 1e-12);
  EXPECT_FALSE(cam.project(Eigen::Vector3d(0.0, 0.0, -1.0), &uv));  // behind
  EXPECT_FALSE(cam.project(Eigen::Vector3d(0.0, 0.0, 0.0), &uv));
  EXPECT_FALSE(cam.project(Eigen::Vector3d(5.0, 0.0, 1.0), &uv));   // right of the image
  EXPECT_FALSE(cam.project(Eigen::Vector3d(0.0, -5.0, 1.0), &uv));  // above the image
  // Pixel-centre convention: the image spans [-0.5, size - 0.5].
  EXPECT_TRUE(cam.in_image({-0.5, -0.5}));
  EXPECT_TRUE(cam.in_image({cam.width - 0.5, cam.height - 0.5}));
  EXPECT_FALSE(cam.in_image({-0.51, 10}));
  EXPECT_FALSE(cam.in_image({10, cam.height - 0.49}));
  EXPECT_FALSE(cam.in_image({3.0, 3.0}, 4.0));
}

TEST(PinholeRadtan, RejectsPointsBeyondTheMonotonicRadius) {
  PinholeRadtan cam = cam0();
  cam.k1 = -0.5;  // r_d = r (1 - 0.5 r^2) folds back at r^2 = 2/3
  cam.k2 = 0.0;
  EXPECT_NEAR(cam.max_valid_radius2(), 2.0 / 3.0, 1e-12);
  Eigen::Vector2d uv;
  // r^2 = 1.2: its distorted image lands inside the image, but it is not a valid projection.
  const Eigen::Vector3d far_out(std::sqrt(1.2), 0.0, 1.0);
  EXPECT_TRUE(cam.in_image(cam.project(far_out)));
  EXPECT_FALSE(cam.project(far_out, &uv));
  EXPECT_TRUE(std::isinf(cam0().max_valid_radius2()));  // EuRoC never folds
}

}  // namespace
}  // namespace hs
