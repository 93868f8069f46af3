// Procedural textures: deterministic, tileable, mipmapped, and rich in corners (except kPlain);
// rendered rooms give plenty of trackable corners.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "common/sim/texture.h"
#include "tests/sim/render_test_util.h"

namespace hs::sim {
namespace {

constexpr int kSize = 256;
const TextureKind kTextured[] = {TextureKind::kMixed, TextureKind::kBrick, TextureKind::kBlobs,
                                 TextureKind::kGravel};

cv::Mat as_mat(const std::vector<uint8_t>& texels, int size) {
  return cv::Mat(size, size, CV_8UC1, const_cast<uint8_t*>(texels.data())).clone();
}

// Shi-Tomasi corners (OpenCV imgproc), as a stand-in for the tracker's FAST/ORB detector.
int corner_count(const cv::Mat& image) {
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(image, corners, 2000, 0.02, 5);
  return static_cast<int>(corners.size());
}

TEST(RenderTexture, DeterministicFromKindAndSeed) {
  for (const TextureKind kind : kTextured) {
    const std::vector<uint8_t> a = generate_texture(kind, 5, kSize);
    EXPECT_EQ(a, generate_texture(kind, 5, kSize));
    EXPECT_NE(a, generate_texture(kind, 6, kSize));
  }
  EXPECT_NE(generate_texture(TextureKind::kMixed, 5, kSize),
            generate_texture(TextureKind::kBrick, 5, kSize));
}

TEST(RenderTexture, TexturedKindsHaveCornersAtSeveralScales) {
  for (const TextureKind kind : kTextured) {
    const cv::Mat t = as_mat(generate_texture(kind, 1, 512), 512);
    cv::Mat half;
    cv::resize(t, half, cv::Size(128, 128), 0, 0, cv::INTER_AREA);
    const int fine = corner_count(t), coarse = corner_count(half);
    std::printf("texture kind %d: %d corners at 512 px, %d at 128 px\n", static_cast<int>(kind),
                fine, coarse);
    // kBlobs trades corners for smooth gradients (for direct alignment).
    EXPECT_GT(fine, kind == TextureKind::kBlobs ? 200 : 500);
    EXPECT_GT(coarse, 40);
    cv::Scalar mean, stddev;
    cv::meanStdDev(t, mean, stddev);
    EXPECT_GT(stddev[0], 25.0);  // strong gradients
    EXPECT_GT(mean[0], 60.0);
    EXPECT_LT(mean[0], 190.0);
  }
}

TEST(RenderTexture, PlainIsNearlyUniformWithWeakShading) {
  const cv::Mat t = as_mat(generate_texture(TextureKind::kPlain, 1, kSize), kSize);
  double lo = 0, hi = 0;
  cv::minMaxLoc(t, &lo, &hi);
  EXPECT_GT(hi - lo, 0.0);  // not perfectly flat
  EXPECT_LT(hi - lo, 12.0);
  // Only low frequencies: neighbouring texels differ by at most one grey level.
  cv::Mat dx, dy;
  cv::absdiff(t.colRange(1, kSize), t.colRange(0, kSize - 1), dx);
  cv::absdiff(t.rowRange(1, kSize), t.rowRange(0, kSize - 1), dy);
  double max_dx = 0, max_dy = 0;
  cv::minMaxLoc(dx, nullptr, &max_dx);
  cv::minMaxLoc(dy, nullptr, &max_dy);
  EXPECT_LE(std::max(max_dx, max_dy), 1.0);
}

TEST(RenderTexture, TilesSeamlessly) {
  // Across the wrap, neighbouring texels differ no more than neighbours inside the tile.
  for (const TextureKind kind : kTextured) {
    const std::vector<uint8_t> t = generate_texture(kind, 2, kSize);
    const auto at = [&](int x, int y) { return static_cast<double>(t[y * kSize + x]); };
    double inside = 0, across_x = 0, across_y = 0;
    for (int i = 0; i < kSize; ++i) {
      inside += std::abs(at(kSize / 2, i) - at(kSize / 2 - 1, i));
      across_x += std::abs(at(0, i) - at(kSize - 1, i));
      across_y += std::abs(at(i, 0) - at(i, kSize - 1));
    }
    EXPECT_LT(across_x, 2.0 * inside + 5 * kSize) << static_cast<int>(kind);
    EXPECT_LT(across_y, 2.0 * inside + 5 * kSize) << static_cast<int>(kind);
  }
}

TEST(RenderTexture, MipmapsAndSampling) {
  const Texture tex(TextureKind::kGravel, 3, 64);
  ASSERT_EQ(tex.levels(), 7);  // 64 .. 1
  for (int y = 0; y < 32; y += 5) {
    for (int x = 0; x < 32; x += 3) {
      const int sum = tex.texel(0, 2 * x, 2 * y) + tex.texel(0, 2 * x + 1, 2 * y) +
                      tex.texel(0, 2 * x, 2 * y + 1) + tex.texel(0, 2 * x + 1, 2 * y + 1);
      EXPECT_EQ(tex.texel(1, x, y), (sum + 2) / 4);
    }
  }
  // Texel centres return the texel at lod 0; in between, the bilinear mix; wrapping.
  EXPECT_FLOAT_EQ(tex.sample(10.5f, 20.5f, 0.0f), tex.texel(0, 10, 20));
  EXPECT_FLOAT_EQ(tex.sample(10.5f + 64, 20.5f - 128, 0.0f), tex.texel(0, 10, 20));
  EXPECT_NEAR(tex.sample(11.0f, 20.5f, 0.0f), 0.5 * (tex.texel(0, 10, 20) + tex.texel(0, 11, 20)),
              1e-4);
  EXPECT_NEAR(tex.sample(64.0f, 0.5f, 0.0f), 0.5 * (tex.texel(0, 63, 0) + tex.texel(0, 0, 0)),
              1e-4);
  // Level 1 centres at lod 1; halfway lods blend the two levels.
  EXPECT_FLOAT_EQ(tex.sample(5.0f, 9.0f, 1.0f), tex.texel(1, 2, 4));
  const float blend = tex.sample(5.0f, 9.0f, 1.5f);
  const float l1 = tex.texel(1, 2, 4), l2 = tex.sample(5.0f, 9.0f, 2.0f);
  EXPECT_NEAR(blend, 0.5f * (l1 + l2), 1e-3);
  // Far beyond the last level: the mean.
  EXPECT_FLOAT_EQ(tex.sample(1.0f, 2.0f, 20.0f), tex.texel(6, 0, 0));
}

TEST(RenderTexture, RenderedRoomHasManyCorners) {
  World world;
  add_room(&world, {-3, -3, 0}, {3, 3, 2.5}, {TextureKind::kMixed, 1, 2.0, 0.9f},
           {TextureKind::kGravel, 10, 2.0, 0.8f}, {TextureKind::kPlain, 20, 3.0, 1.0f});
  Eigen::Isometry3d T_w_box = Eigen::Isometry3d::Identity();
  T_w_box.translation() = Eigen::Vector3d(1.5, 0.0, 0.5);
  add_box(&world, T_w_box, {0.4, 0.4, 0.5}, {TextureKind::kBrick, 30, 1.0, 1.0f});
  RenderOptions options = test::clean_options();
  options.photometric.noise = true;
  options.photometric.vignetting = true;
  Renderer renderer(world, test::euroc_cam0(), options);
  // Camera at 1.2 m height looking along +x (camera z = world x, camera y = world -z).
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
  T_w_c.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  T_w_c.translation() = Eigen::Vector3d(-1.0, 0.3, 1.2);
  const cv::Mat image = renderer.render(T_w_c);
  const int corners = corner_count(image);
  std::printf("rendered room: %d corners\n", corners);
  EXPECT_GT(corners, 500);
}

}  // namespace
}  // namespace hs::sim
