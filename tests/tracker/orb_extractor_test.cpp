// The ORB extractor detects the scale pyramid in two parallel halves: its keypoints must be the
// ones a single cv::ORB pyramid finds (same places, octaves, sizes), spread over the grid, and
// not depend on how many threads ran.
#include <gtest/gtest.h>

#include <opencv2/core/utility.hpp>

#include "common/calib/camera_calib.h"
#include "tests/sim/render_test_util.h"
#include "tracker/orb_extractor.h"

namespace hs {
namespace {

class OrbExtractorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    sim::World world;
    sim::test::add_facing_square(&world, Eigen::Vector3d(0, 0, 3.0), 6.0,
                                 {sim::TextureKind::kMixed, 7, 1.0, 1.0f});
    const PinholeRadtan cam = euroc_stereo_calib().cam0.intrinsics;
    sim::Renderer renderer(world, cam, sim::test::clean_options());
    image_ = renderer.render(Eigen::Isometry3d::Identity());
  }
  cv::Mat image_;
  OrbOptions options_;
};

cv::Ptr<cv::ORB> single_pyramid_orb(const OrbOptions& o) {
  return cv::ORB::create(o.num_features * 3, o.scale_factor, o.num_levels, 19, 0, 2,
                         cv::ORB::FAST_SCORE, 31, o.fast_threshold);
}

// Candidates of one cv::ORB over the whole pyramid, as the extractor's budget asks.
std::vector<cv::KeyPoint> single_pyramid(const cv::Mat& image, const OrbOptions& o) {
  std::vector<cv::KeyPoint> kps;
  single_pyramid_orb(o)->detect(image, kps);
  return kps;
}

TEST_F(OrbExtractorTest, KeypointsAreThoseOfOnePyramid) {
  const std::vector<cv::KeyPoint> reference = single_pyramid(image_, options_);
  const std::vector<cv::KeyPoint> kept = OrbExtractor(options_).detect(image_);
  ASSERT_EQ(kept.size(), static_cast<size_t>(options_.num_features));
  int coarse = 0, found = 0;
  for (const cv::KeyPoint& kp : kept) {
    coarse += kp.octave >= 2;
    // The same corner in the same octave, within the rounding of a level's pixel.
    const double tol = 0.75 * octave_scale(options_, kp.octave);
    for (const cv::KeyPoint& r : reference) {
      if (r.octave == kp.octave && cv::norm(r.pt - kp.pt) <= tol &&
          std::abs(r.size - kp.size) < 1e-3f * r.size) {
        ++found;
        break;
      }
    }
  }
  EXPECT_GT(coarse, 100);  // the downscaled half contributes
  EXPECT_GE(found, static_cast<int>(kept.size()) * 95 / 100);
}

TEST_F(OrbExtractorTest, DescriptorsAreThoseOfOnePyramid) {
  const OrbExtractor orb(options_);
  std::vector<cv::KeyPoint> keypoints = orb.detect(image_);
  // An octave-0 keypoint of our own (as the keyframe builder adds for tracked points), one too
  // close to the border for a descriptor, and class ids that must come back unchanged.
  keypoints.emplace_back(cv::Point2f(300.3f, 200.7f), 31.f, 45.f, 0.f, 0);
  keypoints.emplace_back(cv::Point2f(5.f, 200.f), 31.f, 0.f, 0.f, 0);
  for (size_t i = 0; i < keypoints.size(); ++i) keypoints[i].class_id = static_cast<int>(i) + 7;
  const OrbFeatures ours = orb.describe(image_, keypoints);
  std::vector<cv::KeyPoint> ref_kps = keypoints;
  cv::Mat ref_desc;
  single_pyramid_orb(options_)->compute(image_, ref_kps, ref_desc);
  ASSERT_EQ(ours.size(), ref_kps.size());
  ASSERT_EQ(ours.size(), keypoints.size() - 1);
  ASSERT_EQ(ours.descriptors.rows, static_cast<int>(ours.size()));
  std::vector<int> ref_row(keypoints.size() + 7, -1);
  for (size_t r = 0; r < ref_kps.size(); ++r) ref_row[ref_kps[r].class_id] = static_cast<int>(r);
  // The coarse half's level sizes are rounded from the downscaled image's, so from two levels
  // past the split on a level may be a pixel smaller or larger: a few bits differ there.
  int identical = 0, far = 0;
  double far_bits = 0.0;
  for (size_t i = 0; i < ours.size(); ++i) {
    const cv::KeyPoint& kp = ours.keypoints[i];
    const cv::KeyPoint& given = keypoints[kp.class_id - 7];
    EXPECT_EQ(kp.pt, given.pt);
    EXPECT_EQ(kp.octave, given.octave);
    const int r = ref_row[kp.class_id];
    ASSERT_GE(r, 0);
    const double bits =
        cv::norm(ours.descriptors.row(static_cast<int>(i)), ref_desc.row(r), cv::NORM_HAMMING);
    if (kp.octave < 4) {
      identical += bits == 0.0;
    } else {
      ++far;
      far_bits += bits;
    }
  }
  EXPECT_EQ(identical, static_cast<int>(ours.size()) - far);
  ASSERT_GT(far, 50);
  EXPECT_LT(far_bits / far, 8.0);  // of 256 (unrelated descriptors differ in ~128)
}

TEST_F(OrbExtractorTest, ResultDoesNotDependOnTheThreadCount) {
  const OrbExtractor orb(options_);
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  const OrbFeatures serial = orb.extract(image_);
  cv::setNumThreads(std::max(2, threads));
  const OrbFeatures parallel = orb.extract(image_);
  cv::setNumThreads(threads);
  ASSERT_EQ(serial.size(), parallel.size());
  for (size_t i = 0; i < serial.size(); ++i) {
    EXPECT_EQ(serial.keypoints[i].pt, parallel.keypoints[i].pt);
    EXPECT_EQ(serial.keypoints[i].octave, parallel.keypoints[i].octave);
  }
  EXPECT_EQ(cv::norm(serial.descriptors, parallel.descriptors, cv::NORM_HAMMING), 0.0);
}

TEST_F(OrbExtractorTest, EveryGridRowGetsKeypoints) {
  const std::vector<cv::KeyPoint> kept = OrbExtractor(options_).detect(image_);
  std::vector<int> per_row(options_.grid_rows, 0);
  for (const cv::KeyPoint& kp : kept)
    ++per_row[std::min(options_.grid_rows - 1,
                       static_cast<int>(kp.pt.y * options_.grid_rows / image_.rows))];
  for (int n : per_row) EXPECT_GT(n, 20);
}

}  // namespace
}  // namespace hs
