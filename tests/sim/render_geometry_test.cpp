// The rendered image agrees with PinholeRadtan::project to a small fraction of a pixel.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "tests/sim/render_test_util.h"

namespace hs::sim {
namespace {

using test::add_facing_square;
using test::clean_options;
using test::euroc_cam0;
using test::plain;

constexpr double kBackdropZ = 4.0;

// Intensity centroid of the bright blob in a window around `guess`, background from the
// window border.
Eigen::Vector2d blob_centroid(const cv::Mat& radiance, const Eigen::Vector2d& guess, int r) {
  const int u0 = static_cast<int>(std::lround(guess.x())),
            v0 = static_cast<int>(std::lround(guess.y()));
  double border = 0.0;
  int n = 0;
  for (int dv = -r; dv <= r; ++dv) {
    for (int du = -r; du <= r; ++du) {
      if (std::abs(du) == r || std::abs(dv) == r) {
        border += radiance.at<float>(v0 + dv, u0 + du);
        ++n;
      }
    }
  }
  border /= n;
  double sum = 0.0, su = 0.0, sv = 0.0;
  for (int dv = -r + 1; dv < r; ++dv) {
    for (int du = -r + 1; du < r; ++du) {
      const double w = std::max(0.0, radiance.at<float>(v0 + dv, u0 + du) - border);
      sum += w;
      su += w * (u0 + du);
      sv += w * (v0 + dv);
    }
  }
  return {su / sum, sv / sum};
}

TEST(RenderGeometry, SmallSquaresLandWhereProjectSays) {
  const PinholeRadtan cam = euroc_cam0();
  World world;
  add_facing_square(&world, {0, 0, kBackdropZ}, 20.0, plain(0.1f));
  // ~4 px squares at 2 m on a grid covering the whole image, corners included.
  std::vector<Eigen::Vector3d> centres;
  for (double v = 14; v < cam.height - 14; v += 45) {
    for (double u = 14; u < cam.width - 14; u += 45) {
      centres.push_back(cam.unproject({u + 0.37, v - 0.21}) * 2.0 / cam.unproject({u, v}).z());
      add_facing_square(&world, centres.back(), 0.009, plain(1.6f, 2));
    }
  }
  Renderer renderer(world, cam, clean_options());
  const cv::Mat radiance = renderer.render_radiance(Eigen::Isometry3d::Identity());
  double worst = 0.0, sum = 0.0;
  for (const Eigen::Vector3d& c : centres) {
    const Eigen::Vector2d expected = cam.project(c);
    const double err = (blob_centroid(radiance, expected, 7) - expected).norm();
    worst = std::max(worst, err);
    sum += err;
  }
  std::printf("square centroids vs project(): worst %.4f px, mean %.4f px over %zu\n", worst,
              sum / centres.size(), centres.size());
  EXPECT_LT(worst, 0.1);
  EXPECT_LT(sum / centres.size(), 0.04);
  EXPECT_GT(renderer.stats().edge_pixels, 0);
}

TEST(RenderGeometry, AntiAliasedEdgeSitsAtItsSubpixelPosition) {
  // A bright half-plane whose left edge is a vertical line at x = x_edge (camera frame),
  // z = 2 m; the summed coverage along each row locates the edge.
  const PinholeRadtan cam = euroc_cam0();
  World world;
  add_facing_square(&world, {0, 0, kBackdropZ}, 20.0, plain(0.1f));
  const double x_edge = 0.1234, z = 2.0;
  add_quad(&world, {x_edge, -1.0, z}, {2.0, 0, 0}, {0, 2.0, 0}, plain(1.5f, 2));
  Renderer renderer(world, cam, clean_options());
  const cv::Mat radiance = renderer.render_radiance(Eigen::Isometry3d::Identity());
  double worst = 0.0;
  for (int v = 100; v < 400; v += 7) {
    // Find where the edge crosses row v (the line is curved by the distortion).
    const Eigen::Vector2d ray = cam.unproject_normalised({cam.cx, v});
    Eigen::Vector2d at = cam.project(Eigen::Vector3d(x_edge, ray.y() * z, z));
    for (int it = 0; it < 20; ++it) {  // move along the 3D line until the pixel row is v
      const double y = cam.unproject_normalised(at).y() * z;
      const Eigen::Vector2d next = cam.project(Eigen::Vector3d(x_edge, y, z));
      const Eigen::Vector2d step = cam.project(Eigen::Vector3d(x_edge, y + 1e-3, z)) - next;
      at = cam.project(Eigen::Vector3d(x_edge, y + 1e-3 * (v - next.y()) / step.y(), z));
    }
    ASSERT_NEAR(at.y(), v, 1e-6);
    const int u_left = static_cast<int>(at.x()) - 6, u_right = static_cast<int>(at.x()) + 6;
    const float bg = radiance.at<float>(v, u_left - 3), fg = radiance.at<float>(v, u_right + 3);
    double covered = 0.0;
    for (int u = u_left; u <= u_right; ++u) covered += (radiance.at<float>(v, u) - bg) / (fg - bg);
    const double edge_u = u_right + 0.5 - covered;
    worst = std::max(worst, std::abs(edge_u - at.x()));
  }
  std::printf("anti-aliased edge position: worst %.4f px\n", worst);
  EXPECT_LT(worst, 0.05);
}

TEST(RenderGeometry, NearerQuadWinsWhateverTheOrder) {
  const PinholeRadtan cam = euroc_cam0();
  for (const bool near_first : {true, false}) {
    World world;
    const auto add_far = [&] { add_facing_square(&world, {0, 0, 3.0}, 6.0, plain(0.2f)); };
    const auto add_near = [&] { add_facing_square(&world, {0, 0, 1.5}, 0.3, plain(1.2f)); };
    if (near_first) {
      add_near();
      add_far();
    } else {
      add_far();
      add_near();
    }
    Renderer renderer(world, cam, clean_options());
    const cv::Mat r = renderer.render_radiance(Eigen::Isometry3d::Identity());
    EXPECT_NEAR(r.at<float>(static_cast<int>(cam.cy), static_cast<int>(cam.cx)), 153 * 1.2, 10);
    EXPECT_NEAR(r.at<float>(20, 20), 153 * 0.2, 3);
  }
}

TEST(RenderGeometry, NearPlaneClipsQuads) {
  const PinholeRadtan cam = euroc_cam0();
  RenderOptions options = clean_options();
  options.near_m = 0.1;
  const int u = static_cast<int>(cam.cx), v = static_cast<int>(cam.cy);
  for (const double z : {0.08, 0.12}) {
    World world;
    add_facing_square(&world, {0, 0, 3.0}, 10.0, plain(0.2f));
    add_facing_square(&world, {0, 0, z}, 1.0, plain(1.2f, 2));
    Renderer renderer(world, cam, options);
    const float centre = renderer.render_radiance(Eigen::Isometry3d::Identity()).at<float>(v, u);
    EXPECT_NEAR(centre, z < options.near_m ? 153 * 0.2 : 153 * 1.2, 6) << z;
  }
  // A floor running from behind the camera to far ahead: the part in front is drawn, rows
  // below the horizon see it, nothing is drawn from behind the camera.
  World world;
  add_quad(&world, {-5, 1.0, -5}, {0, 0, 15}, {10, 0, 0}, plain(1.0f));
  Renderer renderer(world, cam, options);
  const cv::Mat r = renderer.render_radiance(Eigen::Isometry3d::Identity());
  EXPECT_NEAR(r.at<float>(cam.height - 5, u), 153, 8);  // floor in front, below
  EXPECT_EQ(r.at<float>(5, u), 0.0f);                   // above the horizon: background
}

TEST(RenderGeometry, CameraPoseMovesTheImage) {
  // Moving the camera by +0.1 m along x shifts a point at depth 2 by -fx * 0.05 px.
  const PinholeRadtan cam = euroc_cam0();
  World world;
  add_facing_square(&world, {0, 0, kBackdropZ}, 20.0, plain(0.1f));
  const Eigen::Vector3d c(0.05, 0.02, 2.0);
  add_facing_square(&world, c, 0.009, plain(1.6f, 2));
  Renderer renderer(world, cam, clean_options());
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
  T_w_c.translation() = Eigen::Vector3d(0.1, 0, 0);
  T_w_c.linear() = Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector2d expected = cam.project(T_w_c.inverse() * c);
  const cv::Mat r = renderer.render_radiance(T_w_c);
  EXPECT_LT((blob_centroid(r, expected, 7) - expected).norm(), 0.1);
}

TEST(RenderGeometry, TextureOffsetShiftsTheTexture) {
  // A 1 m quad starting at x = 0 with offset 0.5 tiles shows what a 2 m quad starting at
  // x = -0.5 without offset shows there.
  const PinholeRadtan cam = euroc_cam0();
  const SurfaceStyle style{TextureKind::kMixed, 4, 1.0, 1.0f};
  World shifted, wide;
  add_quad(&shifted, {0, -0.5, 2}, {1, 0, 0}, {0, 1, 0}, style);
  shifted.quads.back().texture_offset = Eigen::Vector2d(0.5, 0.0);
  add_quad(&wide, {-0.5, -0.5, 2}, {2, 0, 0}, {0, 1, 0}, style);
  const cv::Mat a =
      Renderer(shifted, cam, clean_options()).render_radiance(Eigen::Isometry3d::Identity());
  const cv::Mat b =
      Renderer(wide, cam, clean_options()).render_radiance(Eigen::Isometry3d::Identity());
  const cv::Rect inside(cam.project({0.05, -0.45, 2}).x(), cam.project({0.05, -0.45, 2}).y(),
                        0.8 * cam.fx / 2, 0.8 * cam.fy / 2);
  double max_diff = 0.0;
  cv::minMaxLoc(cv::abs(a(inside) - b(inside)), nullptr, &max_diff);
  EXPECT_LT(max_diff, 0.5);
  EXPECT_GT(cv::norm(a(inside), cv::NORM_L1), 1000.0);  // the region is not empty
}

}  // namespace
}  // namespace hs::sim
