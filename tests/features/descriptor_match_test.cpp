#include "common/features/descriptor_match.h"

#include <gtest/gtest.h>

#include <random>

namespace hs {
namespace {

cv::Mat random_descriptors(int n, std::mt19937& rng) {
  cv::Mat d(n, 32, CV_8U);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < 32; ++c) d.at<uint8_t>(r, c) = static_cast<uint8_t>(byte(rng));
  return d;
}

// Flips `bits` distinct bits of row r.
void flip_bits(cv::Mat& d, int r, int bits) {
  for (int b = 0; b < bits; ++b) d.at<uint8_t>(r, b) ^= 1;
}

TEST(DescriptorMatch, HammingCountsBits) {
  uint8_t a[32] = {}, b[32] = {};
  b[0] = 0xFF;
  b[31] = 0x01;
  EXPECT_EQ(hamming256(a, b), 9);
  EXPECT_EQ(hamming256(a, a), 0);
}

TEST(DescriptorMatch, ProjectionFindsNoisyCopiesNearPrediction) {
  std::mt19937 rng(3);
  const cv::Mat train = random_descriptors(200, rng);
  std::vector<Eigen::Vector2f> uv;
  std::uniform_real_distribution<float> px(0, 700);
  for (int i = 0; i < 200; ++i) uv.emplace_back(px(rng), px(rng) * 0.6f);
  const KeypointGrid grid(uv, 752, 480);

  cv::Mat query = train.rowRange(0, 50).clone();
  std::vector<Eigen::Vector2d> predicted;
  for (int q = 0; q < 50; ++q) {
    flip_bits(query, q, 10);
    predicted.push_back(uv[q].cast<double>() + Eigen::Vector2d(4.0, -3.0));
  }
  predicted[7] += Eigen::Vector2d(100, 0);  // predicted far away: must not match
  const std::vector<int> m = match_by_projection(query, predicted, train, grid, {});
  for (int q = 0; q < 50; ++q) EXPECT_EQ(m[q], q == 7 ? -1 : q) << q;
}

TEST(DescriptorMatch, MutualRejectsAmbiguousAndFar) {
  std::mt19937 rng(5);
  const cv::Mat train = random_descriptors(100, rng);
  cv::Mat query = train.rowRange(0, 20).clone();
  for (int q = 0; q < 20; ++q) flip_bits(query, q, 5);
  random_descriptors(1, rng).copyTo(query.row(3));  // unrelated descriptor
  const auto pairs = match_mutual(query, train, {});
  ASSERT_EQ(pairs.size(), 19u);
  for (const auto& [q, t] : pairs) {
    EXPECT_NE(q, 3);
    EXPECT_EQ(q, t);
  }
}

}  // namespace
}  // namespace hs
