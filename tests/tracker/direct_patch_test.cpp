#include "tracker/direct_patch.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <opencv2/video/tracking.hpp>
#include <stdexcept>

#include "common/calib/camera_calib.h"
#include "tests/tracker/direct_scene.h"

namespace hs {
namespace {

constexpr double kDeg = M_PI / 180.0;
using direct_test::make_pose;

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Reference view at the origin and the current view after direct_test::test_motion().
class PatchAlignTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = std::make_unique<direct_test::RoomScene>(euroc_stereo_calib().cam0.intrinsics);
    ref_img_ = std::make_unique<cv::Mat>(scene_->render(Eigen::Isometry3d::Identity()));
    ref_ = std::make_unique<ImagePyramid>(build_pyramid(*ref_img_, 4));
    points_ = std::make_unique<std::vector<Eigen::Vector3d>>(
        direct_test::select_points(*scene_, *ref_img_, Eigen::Isometry3d::Identity(), 20, 12));
  }
  static void TearDownTestSuite() {
    scene_.reset();
    ref_img_.reset();
    ref_.reset();
    points_.reset();
  }

  const PinholeRadtan& cam() const { return scene_->camera(); }
  Eigen::Vector2d truth(const Eigen::Vector3d& p_ref) const {
    return cam().project(T_true_ * p_ref);
  }
  // Away from surface boundaries in both views, so that the patch sees one plane.
  bool is_interior(const Eigen::Vector3d& p_ref) const {
    return scene_->on_one_surface(Eigen::Isometry3d::Identity(), cam().project(p_ref), 8.0) &&
           scene_->on_one_surface(T_true_.inverse(), truth(p_ref), 8.0);
  }
  // On a plane facing the camera, where the fronto-parallel warp model is exact.
  bool is_fronto_parallel(const Eigen::Vector3d& p_ref) const {
    const auto* rect = scene_->surface_at(Eigen::Isometry3d::Identity(), cam().project(p_ref));
    return rect && std::abs(rect->normal.z()) > 0.99;
  }

  static std::unique_ptr<direct_test::RoomScene> scene_;
  static std::unique_ptr<cv::Mat> ref_img_;
  static std::unique_ptr<ImagePyramid> ref_;
  static std::unique_ptr<std::vector<Eigen::Vector3d>> points_;
  const Eigen::Isometry3d T_true_ = direct_test::test_motion();
  // A pose after sparse alignment, off by ~3 px.
  const Eigen::Isometry3d T_near_ =
      T_true_ * make_pose({0.005, -0.004, 0.003}, Eigen::Vector3d(0.2, 0.3, -0.1) * kDeg);
};

std::unique_ptr<direct_test::RoomScene> PatchAlignTest::scene_;
std::unique_ptr<cv::Mat> PatchAlignTest::ref_img_;
std::unique_ptr<ImagePyramid> PatchAlignTest::ref_;
std::unique_ptr<std::vector<Eigen::Vector3d>> PatchAlignTest::points_;

TEST_F(PatchAlignTest, AffineWarpMatchesFiniteDifferences) {
  const Eigen::Vector3d p_ref(0.7, -0.4, 3.0);
  const Eigen::Matrix2d A = affine_warp_cur_ref(cam(), p_ref, T_true_);
  const Eigen::Vector2d uv = cam().project(p_ref);
  const double h = 1e-3;
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector2d d = h * Eigen::Vector2d::Unit(k);
    const auto at_depth = [&](const Eigen::Vector2d& u) {
      return cam().project(T_true_ * (p_ref.z() * cam().unproject_normalised(u).homogeneous()));
    };
    const Eigen::Vector2d numeric = (at_depth(uv + d) - at_depth(uv - d)) / (2.0 * h);
    EXPECT_LT((A.col(k) - numeric).norm(), 1e-6) << k;
  }
  EXPECT_TRUE(affine_warp_cur_ref(cam(), p_ref, Eigen::Isometry3d::Identity())
                  .isApprox(Eigen::Matrix2d::Identity(), 1e-9));
}

TEST_F(PatchAlignTest, AffineWarpOnASlantedPlaneMatchesFiniteDifferences) {
  // A point on the ground 1.5 m below the camera, seen after 0.5 m of forward motion.
  const Eigen::Vector3d p_ref(0.4, 1.5, 6.0), n_ref(0, -1, 0);
  const Eigen::Isometry3d T_cur_ref = make_pose({0, 0, -0.5}, Eigen::Vector3d(0, 0.01, 0));
  const Eigen::Matrix2d A = affine_warp_cur_ref(cam(), p_ref, T_cur_ref, n_ref);
  const Eigen::Vector2d uv = cam().project(p_ref);
  const auto on_plane = [&](const Eigen::Vector2d& u) {
    const Eigen::Vector3d ray = cam().unproject_normalised(u).homogeneous();
    return cam().project(T_cur_ref * (ray * (n_ref.dot(p_ref) / n_ref.dot(ray))));
  };
  const double h = 1e-3;
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector2d d = h * Eigen::Vector2d::Unit(k);
    const Eigen::Vector2d numeric = (on_plane(uv + d) - on_plane(uv - d)) / (2.0 * h);
    EXPECT_LT((A.col(k) - numeric).norm(), 1e-6) << k;
  }
  // The fronto-parallel warp stretches the ground's rows too little: the patch is compared
  // with the wrong image.
  const Eigen::Matrix2d fronto = affine_warp_cur_ref(cam(), p_ref, T_cur_ref);
  EXPECT_GT(A(1, 1) - fronto(1, 1), 0.05);
  // A normal within 3 deg of the plane of the ray keeps the fronto-parallel warp.
  const Eigen::Vector3d grazing = p_ref.normalized().cross(Eigen::Vector3d::UnitX()).normalized();
  EXPECT_TRUE(affine_warp_cur_ref(cam(), p_ref, T_cur_ref, grazing).isApprox(fronto, 1e-12));
}

TEST(PatchStartLevel, FollowsTheSearchRadius) {
  const PatchAlignOptions options;  // capture radius 2 px
  EXPECT_EQ(patch_start_level(1.0, 4, options), 0);
  EXPECT_EQ(patch_start_level(3.0, 4, options), 1);
  EXPECT_EQ(patch_start_level(6.0, 4, options), 2);
  EXPECT_EQ(patch_start_level(40.0, 4, options), 3);
  EXPECT_EQ(patch_start_level(40.0, 2, options), 1);
}

TEST_F(PatchAlignTest, RefinesCorrespondencesToTheTruePixel) {
  const ImagePyramid cur = build_pyramid(scene_->render(T_true_.inverse()), 4);
  std::vector<PatchAlignResult> results;
  refine_correspondences(*ref_, cur, cam(), *points_, T_near_, 4.0, PatchAlignOptions(), &results);
  ASSERT_EQ(results.size(), points_->size());
  std::vector<double> errors, initial;
  int interior = 0;
  double fronto_max = 0.0;
  for (size_t i = 0; i < points_->size(); ++i) {
    const Eigen::Vector3d& p = (*points_)[i];
    if (!is_interior(p)) continue;
    ++interior;
    if (!results[i].ok()) continue;
    errors.push_back((results[i].uv_cur - truth(p)).norm());
    initial.push_back((cam().project(T_near_ * p) - truth(p)).norm());
    if (is_fronto_parallel(p)) fronto_max = std::max(fronto_max, errors.back());
    EXPECT_NEAR(results[i].gain, 1.0, 0.05);
  }
  ASSERT_GT(interior, 150);
  EXPECT_GT(errors.size(), 0.97 * interior);
  EXPECT_GT(median(initial), 1.0);
  EXPECT_LT(median(errors), 0.05);
  EXPECT_LT(fronto_max, 0.1);  // slanted planes deviate from the fronto-parallel warp
}

TEST_F(PatchAlignTest, FitsAffineBrightness) {
  const ImagePyramid cur = build_pyramid(scene_->render(T_true_.inverse(), 1.4, 10.0), 4);
  std::vector<PatchAlignResult> results;
  refine_correspondences(*ref_, cur, cam(), *points_, T_near_, 4.0, PatchAlignOptions(), &results);
  std::vector<double> errors, gains, biases;
  for (size_t i = 0; i < points_->size(); ++i) {
    if (!is_interior((*points_)[i]) || !results[i].ok()) continue;
    errors.push_back((results[i].uv_cur - truth((*points_)[i])).norm());
    gains.push_back(results[i].gain);
    biases.push_back(results[i].bias);
  }
  ASSERT_GT(errors.size(), 150u);
  EXPECT_LT(median(errors), 0.05);
  EXPECT_NEAR(median(gains), 1.4, 0.03);
  EXPECT_NEAR(median(biases), 10.0, 3.0);
}

// Optical flow from the previous pixel over > 15 px, against OpenCV's pyramidal LK (8x8, 4
// levels): as accurate under constant brightness, better when it changes.
TEST_F(PatchAlignTest, OpticalFlowFollowsLargeMotion) {
  std::vector<Eigen::Vector2d> uv_prev;
  std::vector<cv::Point2f> cv_prev;
  for (const auto& p : *points_) {
    uv_prev.push_back(cam().project(p));
    cv_prev.emplace_back(static_cast<float>(uv_prev.back().x()),
                         static_cast<float>(uv_prev.back().y()));
  }
  for (const double gain : {1.0, 1.2}) {
    SCOPED_TRACE(gain);
    const cv::Mat cur_img = scene_->render(T_true_.inverse(), gain, 8.0 * (gain - 1.0) / 0.2);
    std::vector<PatchAlignResult> results;
    track_optical_flow(*ref_, build_pyramid(cur_img, 4), uv_prev, uv_prev, 40.0,
                       PatchAlignOptions(), &results);
    std::vector<cv::Point2f> cv_cur;
    std::vector<uint8_t> cv_status;
    std::vector<float> cv_err;
    cv::calcOpticalFlowPyrLK(*ref_img_, cur_img, cv_prev, cv_cur, cv_status, cv_err, cv::Size(8, 8),
                             3);
    std::vector<double> motion, errors, cv_errors;
    int interior = 0;
    for (size_t i = 0; i < points_->size(); ++i) {
      const Eigen::Vector3d& p = (*points_)[i];
      if (!is_interior(p)) continue;
      ++interior;
      motion.push_back((truth(p) - uv_prev[i]).norm());
      if (results[i].ok()) errors.push_back((results[i].uv_cur - truth(p)).norm());
      if (cv_status[i]) {
        cv_errors.push_back((Eigen::Vector2d(cv_cur[i].x, cv_cur[i].y) - truth(p)).norm());
      }
    }
    ASSERT_GT(interior, 150);
    EXPECT_GT(median(motion), 15.0);
    EXPECT_GT(errors.size(), 0.95 * interior);
    // Translation-only patches under a 3 degree rotation: short of the refinement's accuracy.
    EXPECT_LT(median(errors), 0.1);
    if (gain == 1.0) {
      EXPECT_LT(median(errors), median(cv_errors) + 0.03);
    } else {
      EXPECT_LT(median(errors), median(cv_errors));
    }
  }
}

TEST_F(PatchAlignTest, OccludedPointsFail) {
  cv::Mat cur_img = scene_->render(T_true_.inverse());
  const cv::Rect box(380, 60, 300, 200);
  cur_img(box).setTo(cv::Scalar(120));
  const ImagePyramid cur = build_pyramid(cur_img, 4);
  std::vector<PatchAlignResult> results;
  refine_correspondences(*ref_, cur, cam(), *points_, T_near_, 4.0, PatchAlignOptions(), &results);
  const cv::Rect inner(box.x + 8, box.y + 8, box.width - 16, box.height - 16);
  int occluded = 0;
  for (size_t i = 0; i < points_->size(); ++i) {
    const Eigen::Vector2d uv = truth((*points_)[i]);
    if (!inner.contains(cv::Point(static_cast<int>(uv.x()), static_cast<int>(uv.y())))) continue;
    ++occluded;
    EXPECT_FALSE(results[i].ok()) << i << " " << to_string(results[i].status);
  }
  EXPECT_GT(occluded, 20);
}

TEST_F(PatchAlignTest, HandlesPointsOutsideTheImage) {
  const ImagePyramid cur = build_pyramid(scene_->render(T_true_.inverse()), 4);
  const PatchAlignOptions options;
  const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
  // Reference patch cut by the border, guess outside, guess not finite.
  EXPECT_EQ(align_patch(*ref_, {1.0, 1.0}, I, cur, {1.0, 1.0}, 1.0, options).status,
            PatchAlignStatus::kOutOfImage);
  EXPECT_EQ(align_patch(*ref_, {300.0, 200.0}, I, cur, {-40.0, 200.0}, 1.0, options).status,
            PatchAlignStatus::kOutOfImage);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(align_patch(*ref_, {300.0, 200.0}, I, cur, {nan, 200.0}, 1.0, options).status,
            PatchAlignStatus::kOutOfImage);
  // Behind the reference camera; seen near the reference border but outside the current image.
  std::vector<Eigen::Vector3d> pts = {{0.0, 0.0, -1.0}};
  for (const double u : {14.0, 737.0}) {
    for (const double v : {14.0, 240.0, 465.0}) {
      const Eigen::Vector3d p = 4.0 * cam().unproject_normalised({u, v}).homogeneous();
      if (pts.size() < 2 && !cam().in_image(truth(p), -3.0)) pts.push_back(p);
    }
  }
  ASSERT_EQ(pts.size(), 2u);
  std::vector<PatchAlignResult> results;
  refine_correspondences(*ref_, cur, cam(), pts, T_true_, 4.0, options, &results);
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[0].status, PatchAlignStatus::kOutOfImage);
  EXPECT_EQ(results[1].status, PatchAlignStatus::kOutOfImage);
  EXPECT_THROW(track_optical_flow(*ref_, cur, {{1.0, 1.0}}, {}, 4.0, options, &results),
               std::invalid_argument);
}

TEST_F(PatchAlignTest, RejectsPatchesWithoutTexture) {
  const ImagePyramid flat = build_pyramid(cv::Mat(480, 752, CV_8UC1, cv::Scalar(90)), 4);
  cv::Mat stripes(480, 752, CV_8UC1);
  for (int v = 0; v < stripes.rows; ++v)
    for (int u = 0; u < stripes.cols; ++u)
      stripes.at<uint8_t>(v, u) = static_cast<uint8_t>(100 + 60 * std::sin(u * 0.4));
  const ImagePyramid edge = build_pyramid(stripes, 4);  // the aperture problem
  const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
  for (const ImagePyramid* pyr : {&flat, &edge}) {
    EXPECT_EQ(align_patch(*pyr, {300.0, 200.0}, I, *pyr, {301.0, 200.5}, 2.0, {}).status,
              PatchAlignStatus::kNoTexture);
  }
}

}  // namespace
}  // namespace hs
