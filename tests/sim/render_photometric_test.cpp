// Each photometric switch does what it says; images are deterministic given the seed.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>

#include "tests/sim/render_test_util.h"

namespace hs::sim {
namespace {

using test::add_facing_square;
using test::clean_options;
using test::euroc_cam0;
using test::plain;

// A textured wall filling the view at 2 m, dim enough that gain 1.4 does not saturate.
World wall(TextureKind kind = TextureKind::kMixed, float brightness = 0.45f) {
  World world;
  add_facing_square(&world, {0, 0, 2.0}, 6.0, {kind, 7, 1.0, brightness});
  return world;
}

cv::Mat quantised(const cv::Mat& radiance) {
  cv::Mat out;
  radiance.convertTo(out, CV_8U);
  return out;
}

TEST(RenderPhotometric, NoiseOffGivesTheNoiselessRender) {
  Renderer renderer(wall(), euroc_cam0(), clean_options());
  const cv::Mat image = renderer.render(Eigen::Isometry3d::Identity());
  const cv::Mat clean = quantised(renderer.render_radiance(Eigen::Isometry3d::Identity()));
  ASSERT_EQ(image.type(), CV_8UC1);
  ASSERT_EQ(image.size(), cv::Size(752, 480));
  EXPECT_EQ(cv::countNonZero(image != clean), 0);
  // Noise off is deterministic whatever the seed.
  FrameParams other;
  other.noise_seed = 99;
  EXPECT_EQ(cv::countNonZero(renderer.render(Eigen::Isometry3d::Identity(), other) != image), 0);
}

TEST(RenderPhotometric, NoiseHasTheConfiguredStatistics) {
  RenderOptions options = clean_options();
  options.photometric.noise = true;
  Renderer renderer(wall(TextureKind::kPlain, 0.8f), euroc_cam0(), options);
  const cv::Mat clean = renderer.render_radiance(Eigen::Isometry3d::Identity());
  cv::Mat noisy;
  renderer.render(Eigen::Isometry3d::Identity()).convertTo(noisy, CV_32F);
  cv::Scalar mean, stddev;
  cv::meanStdDev(noisy - clean, mean, stddev);
  const double level = cv::mean(clean)[0];
  const PhotometricOptions& p = options.photometric;
  // Quantisation adds 1/12 grey level^2.
  const double expected =
      std::sqrt(p.read_noise_dn * p.read_noise_dn + p.shot_noise_gain * level + 1.0 / 12.0);
  EXPECT_NEAR(mean[0], 0.0, 0.05);
  EXPECT_NEAR(stddev[0], expected, 0.05 * expected);
}

TEST(RenderPhotometric, SameSeedGivesByteIdenticalImages) {
  RenderOptions options = clean_options();
  options.photometric.noise = true;
  options.photometric.vignetting = true;
  Renderer a(wall(), euroc_cam0(), options);
  Renderer b(wall(), euroc_cam0(), options);
  FrameParams f;
  f.noise_seed = 12345;
  const Eigen::Isometry3d pose(Eigen::Translation3d(0.1, -0.05, 0.2));
  const cv::Mat first = a.render(pose, f);
  EXPECT_EQ(cv::countNonZero(a.render(pose, f) != first), 0);
  EXPECT_EQ(cv::countNonZero(b.render(pose, f) != first), 0);
  f.noise_seed = 12346;
  EXPECT_GT(cv::countNonZero(a.render(pose, f) != first), 100000);
}

TEST(RenderPhotometric, GainScalesIntensity) {
  Renderer renderer(wall(), euroc_cam0(), clean_options());
  const cv::Mat base = renderer.render(Eigen::Isometry3d::Identity());
  FrameParams bright;
  bright.gain = 1.4;
  const cv::Mat brighter = renderer.render(Eigen::Isometry3d::Identity(), bright);
  double max_value = 0.0;
  cv::minMaxLoc(base, nullptr, &max_value);
  ASSERT_LT(max_value * 1.4, 255.0);  // no saturation, so the ratio is exact up to rounding
  EXPECT_NEAR(cv::mean(brighter)[0] / cv::mean(base)[0], 1.4, 0.01);
}

TEST(RenderPhotometric, VignettingDarkensCorners) {
  RenderOptions options = clean_options();
  const World world = wall(TextureKind::kPlain, 1.0f);
  Renderer flat(world, euroc_cam0(), options);
  options.photometric.vignetting = true;
  options.photometric.vignetting_strength = 0.5f;
  Renderer vignetted(world, euroc_cam0(), options);
  cv::Mat a, b;
  flat.render(Eigen::Isometry3d::Identity()).convertTo(a, CV_32F);
  vignetted.render(Eigen::Isometry3d::Identity()).convertTo(b, CV_32F);
  const PinholeRadtan cam = euroc_cam0();
  const int cu = static_cast<int>(cam.cx), cv_ = static_cast<int>(cam.cy);
  EXPECT_NEAR(b.at<float>(cv_, cu) / a.at<float>(cv_, cu), 1.0, 0.01);
  const Photometric model(cam, options.photometric);
  for (const cv::Point& corner :
       {cv::Point(2, 2), cv::Point(749, 2), cv::Point(2, 477), cv::Point(749, 477)}) {
    const float ratio = b.at<float>(corner) / a.at<float>(corner);
    EXPECT_LT(ratio, 0.9f);
    EXPECT_NEAR(ratio, model.vignetting(corner.x, corner.y), 0.01);
  }
}

TEST(RenderPhotometric, BlackoutIsBlack) {
  RenderOptions options = clean_options();
  options.photometric.noise = true;
  Renderer renderer(wall(), euroc_cam0(), options);
  FrameParams f;
  f.blackout = true;
  const cv::Mat image = renderer.render(Eigen::Isometry3d::Identity(), f);
  ASSERT_EQ(image.size(), cv::Size(752, 480));
  EXPECT_EQ(cv::countNonZero(image), 0);
}

// Gradient energy: blur lowers it.
double sharpness(const cv::Mat& radiance) {
  double sum = 0.0;
  for (int v = 0; v < radiance.rows; ++v) {
    for (int u = 1; u < radiance.cols; ++u) {
      const double d = radiance.at<float>(v, u) - radiance.at<float>(v, u - 1);
      sum += d * d;
    }
  }
  return sum;
}

TEST(RenderPhotometric, MotionBlurFollowsTheExposurePoses) {
  RenderOptions options = clean_options();
  options.motion_blur = true;
  Renderer renderer(wall(), euroc_cam0(), options);
  const Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  const cv::Mat sharp = renderer.render_radiance(pose);

  FrameParams still;  // a pose function that does not move: no tile needs blurring
  still.T_w_c_at = [&](double) { return pose; };
  EXPECT_EQ(cv::countNonZero(renderer.render_radiance(pose, still) != sharp), 0);
  EXPECT_EQ(renderer.stats().blurred_tiles, 0);

  // Yaw of 0.02 rad during the exposure: ~9 px of motion, every tile is blurred.
  FrameParams moving;
  moving.T_w_c_at = [&](double s) {
    return Eigen::Isometry3d(Eigen::AngleAxisd(0.02 * (s - 0.5), Eigen::Vector3d::UnitY()));
  };
  const cv::Mat blurred = renderer.render_radiance(pose, moving);
  EXPECT_EQ(renderer.stats().blurred_tiles, 47 * 30);
  EXPECT_LT(sharpness(blurred), 0.6 * sharpness(sharp));
  EXPECT_NEAR(cv::mean(blurred)[0], cv::mean(sharp)[0], 1.0);  // blur keeps the brightness

  // Blur off: the pose function is ignored.
  options.motion_blur = false;
  Renderer no_blur(wall(), euroc_cam0(), options);
  EXPECT_EQ(cv::countNonZero(no_blur.render_radiance(pose, moving) != sharp), 0);
}

}  // namespace
}  // namespace hs::sim
