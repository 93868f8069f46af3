// cam0 and cam1 renders of a plane at known depth are consistent: block matching finds the
// disparities the ground-truth depth predicts, and triangulating them gives the depth back.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "tests/sim/render_test_util.h"

namespace hs::sim {
namespace {

using test::clean_options;

// Normalised cross-correlation of a (2r+1)^2 patch of a at (ua, va) and of b at (ub, vb).
double ncc(const cv::Mat& a, int ua, int va, const cv::Mat& b, int ub, int vb, int r) {
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  const int n = (2 * r + 1) * (2 * r + 1);
  for (int dv = -r; dv <= r; ++dv) {
    for (int du = -r; du <= r; ++du) {
      const double x = a.at<float>(va + dv, ua + du), y = b.at<float>(vb + dv, ub + du);
      sa += x;
      sb += y;
      saa += x * x;
      sbb += y * y;
      sab += x * y;
    }
  }
  const double cov = sab - sa * sb / n;
  return cov / std::sqrt((saa - sa * sa / n) * (sbb - sb * sb / n) + 1e-9);
}

// Sub-pixel match by Lucas-Kanade (translation, bilinear interpolation) from `start`: the
// position in b of the (2r+1)^2 patch of a centred at pixel `at`.
Eigen::Vector2d refine(const cv::Mat& a, const cv::Point& at, const cv::Mat& b,
                       Eigen::Vector2d start, int r) {
  const cv::Size size(2 * r + 1, 2 * r + 1);
  const cv::Mat templ = a(cv::Rect(at.x - r, at.y - r, size.width, size.height));
  Eigen::Vector2d pos = start;
  for (int it = 0; it < 30; ++it) {
    cv::Mat patch, gx, gy;
    // One pixel larger on each side for central-difference gradients.
    cv::getRectSubPix(b, cv::Size(size.width + 2, size.height + 2), cv::Point2f(pos.x(), pos.y()),
                      patch);
    Eigen::Matrix2d H = Eigen::Matrix2d::Zero();
    Eigen::Vector2d g = Eigen::Vector2d::Zero();
    for (int y = 1; y <= size.height; ++y) {
      for (int x = 1; x <= size.width; ++x) {
        const Eigen::Vector2d grad(0.5 * (patch.at<float>(y, x + 1) - patch.at<float>(y, x - 1)),
                                   0.5 * (patch.at<float>(y + 1, x) - patch.at<float>(y - 1, x)));
        const double e = patch.at<float>(y, x) - templ.at<float>(y - 1, x - 1);
        H += grad * grad.transpose();
        g += grad * e;
      }
    }
    const Eigen::Vector2d step = -H.ldlt().solve(g);
    pos += step;
    if (step.norm() < 1e-4) break;
  }
  return pos;
}

TEST(RenderStereo, BlockMatchingRecoversTheDepth) {
  const StereoCalib calib = euroc_stereo_calib();
  const double depth = 2.5;  // plane z = depth in cam0's frame
  World world;
  add_quad(&world, {-8, -8, depth}, {16, 0, 0}, {0, 16, 0}, {TextureKind::kMixed, 3, 1.0, 1.0f});
  const Eigen::Isometry3d T_w_c0 = Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d T_w_c1 = T_w_c0 * calib.T_c0_c1();
  Renderer r0(world, calib.cam0.intrinsics, clean_options());
  Renderer r1(r0, calib.cam1.intrinsics, clean_options());
  const cv::Mat img0 = r0.render_radiance(T_w_c0), img1 = r1.render_radiance(T_w_c1);

  const PinholeRadtan& k0 = calib.cam0.intrinsics;
  const PinholeRadtan& k1 = calib.cam1.intrinsics;
  const int r = 7;
  std::vector<double> match_err, depth_err;
  size_t patches = 0;
  for (int v = 60; v < 430; v += 40) {
    for (int u = 120; u < 640; u += 40) {
      // Search from where a point at infinity would appear, 60 px along the baseline and
      // +-3 px across it (the depth itself is not used).
      const Eigen::Vector2d inf =
          k1.project(calib.T_c0_c1().linear().transpose() * k0.unproject({u, v}));
      const int iu = static_cast<int>(std::lround(inf.x())),
                iv = static_cast<int>(std::lround(inf.y()));
      double best = -2;
      int bu = 0, bv = 0;
      for (int dv = -3; dv <= 3; ++dv) {
        for (int du = -60; du <= 2; ++du) {
          const double score = ncc(img0, u, v, img1, iu + du, iv + dv, r);
          if (score > best) {
            best = score;
            bu = iu + du;
            bv = iv + dv;
          }
        }
      }
      ++patches;
      if (best < 0.8) continue;  // weakly textured patch
      const Eigen::Vector2d found = refine(img0, {u, v}, img1, {bu, bv}, r);
      // Ground truth: intersect cam0's ray with the plane, project into cam1.
      const Eigen::Vector3d p_c0 = k0.unproject({u, v}) * (depth / k0.unproject({u, v}).z());
      const Eigen::Vector2d expected = k1.project(calib.T_c0_c1().inverse() * p_c0);
      match_err.push_back((found - expected).norm());
      // Triangulate the match (midpoint of the two rays) and compare the depth.
      const Eigen::Vector3d d0 = k0.unproject({u, v});
      const Eigen::Vector3d d1 = calib.T_c0_c1().linear() * k1.unproject(found);
      const Eigen::Vector3d o1 = calib.T_c0_c1().translation();
      Eigen::Matrix<double, 3, 2> A;
      A << d0, -d1;
      const Eigen::Vector2d st = A.colPivHouseholderQr().solve(o1);
      const Eigen::Vector3d p = 0.5 * (st[0] * d0 + o1 + st[1] * d1);
      depth_err.push_back(std::abs(p.z() - depth) / depth);
    }
  }
  ASSERT_GT(match_err.size(), patches * 8 / 10);
  std::sort(match_err.begin(), match_err.end());
  std::sort(depth_err.begin(), depth_err.end());
  const double median = match_err[match_err.size() / 2];
  std::printf(
      "stereo: %zu matches, median error %.3f px, worst %.3f px; median depth error %.3f%%\n",
      match_err.size(), median, match_err.back(), 100 * depth_err[depth_err.size() / 2]);
  EXPECT_LT(median, 0.1);
  EXPECT_LT(match_err.back(), 0.3);
  EXPECT_LT(depth_err[depth_err.size() / 2], 0.005);
}

}  // namespace
}  // namespace hs::sim
