#include "tracker/direct_align.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "common/calib/camera_calib.h"
#include "common/imu/so3.h"
#include "tests/tracker/direct_scene.h"

namespace hs {
namespace {

constexpr double kDeg = M_PI / 180.0;

using direct_test::make_pose;

double translation_error(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.inverse() * b).translation().norm();
}

double rotation_error_deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return so3::log(Eigen::Matrix3d(a.linear().transpose() * b.linear())).norm() / kDeg;
}

// Reference view at the world origin, current view after a known motion (8.5 cm, 3 deg).
class SparseAlignTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = std::make_unique<direct_test::RoomScene>(euroc_stereo_calib().cam0.intrinsics);
    const cv::Mat ref_img = scene_->render(Eigen::Isometry3d::Identity(), 1.0, 0.0, 1.0, 1);
    ref_ = std::make_unique<ImagePyramid>(build_pyramid(ref_img, 4));
    points_ = std::make_unique<std::vector<Eigen::Vector3d>>(
        direct_test::select_points(*scene_, ref_img, Eigen::Isometry3d::Identity(), 20, 12));
  }
  static void TearDownTestSuite() {
    scene_.reset();
    ref_.reset();
    points_.reset();
  }

  static ImagePyramid render_cur(const Eigen::Isometry3d& T_cur_ref, double gain = 1.0,
                                 double offset = 0.0) {
    return build_pyramid(scene_->render(T_cur_ref.inverse(), gain, offset, 1.0, 2), 4);
  }

  const PinholeRadtan& cam() const { return scene_->camera(); }

  // Away from surface boundaries in both views.
  bool is_interior(const Eigen::Vector3d& p_ref) const {
    return scene_->on_one_surface(Eigen::Isometry3d::Identity(), cam().project(p_ref), 6.0) &&
           scene_->on_one_surface(T_true_.inverse(), cam().project(T_true_ * p_ref), 6.0);
  }

  static std::unique_ptr<direct_test::RoomScene> scene_;
  static std::unique_ptr<ImagePyramid> ref_;
  static std::unique_ptr<std::vector<Eigen::Vector3d>> points_;
  const Eigen::Isometry3d T_true_ = direct_test::test_motion();
};

std::unique_ptr<direct_test::RoomScene> SparseAlignTest::scene_;
std::unique_ptr<ImagePyramid> SparseAlignTest::ref_;
std::unique_ptr<std::vector<Eigen::Vector3d>> SparseAlignTest::points_;

// Initial guess off by an IMU-like prediction error.
Eigen::Isometry3d perturb(const Eigen::Isometry3d& T, double trans_m, double rot_deg) {
  return T * make_pose(Eigen::Vector3d(1.0, -0.5, 0.7).normalized() * trans_m,
                       Eigen::Vector3d(-0.4, 0.8, 0.3).normalized() * rot_deg * kDeg);
}

// Median image motion (level-0 pixels) between the projections under two poses.
double median_pixel_shift(const PinholeRadtan& cam, const std::vector<Eigen::Vector3d>& pts,
                          const Eigen::Isometry3d& A, const Eigen::Isometry3d& B) {
  std::vector<double> d;
  for (const auto& p : pts) d.push_back((cam.project(A * p) - cam.project(B * p)).norm());
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2];
}

TEST_F(SparseAlignTest, RecoversPoseFromImuLikeError) {
  ASSERT_GT(points_->size(), 200u);
  const ImagePyramid cur = render_cur(T_true_);
  const Eigen::Isometry3d T_init = perturb(T_true_, 0.03, 1.5);
  SparseAligner aligner;
  const SparseAlignResult r = aligner.align(*ref_, cur, cam(), *points_, T_init);
  ASSERT_TRUE(r.valid()) << to_string(r.status);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(translation_error(r.T_cur_ref, T_true_), 0.002);
  EXPECT_LT(rotation_error_deg(r.T_cur_ref, T_true_), 0.05);
  // The translated-patch approximation dilutes the gain estimate by ~1%.
  EXPECT_NEAR(r.brightness.a, 0.0, 0.02);
  EXPECT_NEAR(r.brightness.b, 0.0, 2.0);
  ASSERT_EQ(r.inlier.size(), points_->size());
  ASSERT_EQ(r.residual.size(), points_->size());
  // Patches on one surface are inliers; those across seams and occlusion edges need not be.
  int interior = 0, interior_inliers = 0;
  for (size_t i = 0; i < points_->size(); ++i) {
    if (!is_interior((*points_)[i])) continue;
    ++interior;
    interior_inliers += r.inlier[i];
  }
  EXPECT_GT(interior, 150);
  EXPECT_GT(interior_inliers, 0.95 * interior);
  // The covariance is symmetric positive definite.
  EXPECT_TRUE(r.covariance.isApprox(r.covariance.transpose(), 1e-9));
  using Matrix6d = Eigen::Matrix<double, 6, 6>;
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Matrix6d>(r.covariance).eigenvalues().minCoeff(), 0.0);
}

TEST_F(SparseAlignTest, PyramidConvergesFromLargeInitialError) {
  const ImagePyramid cur = render_cur(T_true_);
  const Eigen::Isometry3d T_init = perturb(T_true_, 0.08, 3.0);
  ASSERT_GT(median_pixel_shift(cam(), *points_, T_init, T_true_), 15.0);
  SparseAligner aligner;
  const SparseAlignResult r = aligner.align(*ref_, cur, cam(), *points_, T_init);
  ASSERT_TRUE(r.valid()) << to_string(r.status);
  EXPECT_LT(translation_error(r.T_cur_ref, T_true_), 0.002);
  EXPECT_LT(rotation_error_deg(r.T_cur_ref, T_true_), 0.05);

  // Starting at the finest level only, the same error is out of reach.
  SparseAlignOptions fine_only;
  fine_only.coarsest_level = 0;
  const SparseAlignResult f = SparseAligner(fine_only).align(*ref_, cur, cam(), *points_, T_init);
  EXPECT_GT(translation_error(f.T_cur_ref, T_true_), 0.01);
}

TEST_F(SparseAlignTest, EstimatesAffineBrightness) {
  const ImagePyramid cur = render_cur(T_true_, 1.4, 10.0);
  const Eigen::Isometry3d T_init = perturb(T_true_, 0.03, 1.5);
  SparseAligner aligner;
  const SparseAlignResult r = aligner.align(*ref_, cur, cam(), *points_, T_init);
  ASSERT_TRUE(r.valid()) << to_string(r.status);
  EXPECT_NEAR(r.brightness.a, std::log(1.4), 0.02);
  EXPECT_NEAR(r.brightness.b, 10.0, 2.0);
  EXPECT_LT(translation_error(r.T_cur_ref, T_true_), 0.002);
  EXPECT_LT(rotation_error_deg(r.T_cur_ref, T_true_), 0.05);
}

TEST_F(SparseAlignTest, OccludedPatchesAreFlaggedAndDownWeighted) {
  cv::Mat cur_img = scene_->render(T_true_.inverse(), 1.0, 0.0, 1.0, 2);
  // An occluder with its own texture over a quarter of the image.
  const cv::Rect box(380, 60, 300, 200);
  for (int v = box.y; v < box.y + box.height; ++v)
    for (int u = box.x; u < box.x + box.width; ++u)
      cur_img.at<uint8_t>(v, u) = static_cast<uint8_t>(
          std::clamp(direct_test::texture({u * 0.004, v * 0.004}, 99), 0.0, 255.0));
  const ImagePyramid cur = build_pyramid(cur_img, 4);
  SparseAligner aligner;
  const SparseAlignResult r =
      aligner.align(*ref_, cur, cam(), *points_, perturb(T_true_, 0.03, 1.5));
  ASSERT_TRUE(r.valid()) << to_string(r.status);
  EXPECT_LT(translation_error(r.T_cur_ref, T_true_), 0.002);
  EXPECT_LT(rotation_error_deg(r.T_cur_ref, T_true_), 0.05);
  int occluded = 0, occluded_flagged = 0, clear = 0, clear_inliers = 0;
  const cv::Rect inner(box.x + 4, box.y + 4, box.width - 8, box.height - 8);
  const cv::Rect outer(box.x - 4, box.y - 4, box.width + 8, box.height + 8);
  for (size_t i = 0; i < points_->size(); ++i) {
    const Eigen::Vector2d uv = cam().project(T_true_ * (*points_)[i]);
    const cv::Point pt(static_cast<int>(std::lround(uv.x())),
                       static_cast<int>(std::lround(uv.y())));
    if (inner.contains(pt)) {
      ++occluded;
      occluded_flagged += !r.inlier[i];
    } else if (!outer.contains(pt) && r.residual[i] >= 0.f && is_interior((*points_)[i])) {
      ++clear;
      clear_inliers += r.inlier[i];
    }
  }
  ASSERT_GT(occluded, 20);
  EXPECT_GT(occluded_flagged, 0.9 * occluded);
  EXPECT_GT(clear_inliers, 0.95 * clear);
}

TEST_F(SparseAlignTest, SkipsPointsOutsideTheImages) {
  const ImagePyramid cur = render_cur(T_true_);
  std::vector<Eigen::Vector3d> pts = *points_;
  const size_t n_good = pts.size();
  pts.push_back({0.0, 0.0, -2.0});  // behind the reference camera
  pts.push_back({50.0, 0.0, 2.0});  // outside the reference image
  // Inside the reference image near its border, outside the current one.
  bool found = false;
  for (const double u : {14.0, 737.0}) {
    for (const double v : {14.0, 240.0, 465.0}) {
      const Eigen::Vector3d p = 4.0 * cam().unproject_normalised({u, v}).homogeneous();
      if (!found && !cam().in_image(cam().project(T_true_ * p), -3.0)) {
        pts.push_back(p);
        found = true;
      }
    }
  }
  ASSERT_TRUE(found);
  SparseAligner aligner;
  const SparseAlignResult r = aligner.align(*ref_, cur, cam(), pts, perturb(T_true_, 0.03, 1.5));
  ASSERT_TRUE(r.valid()) << to_string(r.status);
  EXPECT_LT(translation_error(r.T_cur_ref, T_true_), 0.002);
  for (size_t i = n_good; i < pts.size(); ++i) {
    EXPECT_FALSE(r.inlier[i]) << i;
    EXPECT_EQ(r.residual[i], -1.f) << i;
  }
  EXPECT_LE(r.num_valid, static_cast<int>(n_good));

  // Nothing usable at all: a clear failure, not a crash.
  const std::vector<Eigen::Vector3d> bad(pts.end() - 3, pts.end());
  const SparseAlignResult f = aligner.align(*ref_, cur, cam(), bad, T_true_);
  EXPECT_EQ(f.status, SparseAlignStatus::kTooFewPoints);
  EXPECT_FALSE(f.valid());
  EXPECT_EQ(f.num_valid, 0);
}

TEST_F(SparseAlignTest, RotationPriorPullsTowardsThePrediction) {
  const ImagePyramid cur = render_cur(T_true_);
  const Eigen::Isometry3d T_init = perturb(T_true_, 0.03, 1.5);
  RotationPrior prior;
  prior.R_cur_ref = T_true_.linear() * so3::exp(Eigen::Vector3d(0.0, 0.0, 1.0 * kDeg));
  SparseAligner aligner;
  // A weak prior (1 deg sigma) barely matters next to the photometric information.
  prior.information = Eigen::Matrix3d::Identity() / (kDeg * kDeg);
  const SparseAlignResult weak = aligner.align(*ref_, cur, cam(), *points_, T_init, {}, &prior);
  ASSERT_TRUE(weak.valid());
  EXPECT_LT(rotation_error_deg(weak.T_cur_ref, T_true_), 0.05);
  // A very strong one wins.
  prior.information = Eigen::Matrix3d::Identity() * 1e12;
  const SparseAlignResult strong = aligner.align(*ref_, cur, cam(), *points_, T_init, {}, &prior);
  Eigen::Isometry3d T_prior = T_true_;
  T_prior.linear() = prior.R_cur_ref;
  EXPECT_LT(rotation_error_deg(strong.T_cur_ref, T_prior), 0.01);
}

TEST_F(SparseAlignTest, FixedBrightnessKeepsTheGivenValues) {
  const ImagePyramid cur = render_cur(T_true_, 1.4, 10.0);
  SparseAlignOptions options;
  options.estimate_affine = false;
  const AffineBrightness given{std::log(1.4), 10.0};
  const SparseAlignResult r =
      SparseAligner(options).align(*ref_, cur, cam(), *points_, perturb(T_true_, 0.03, 1.5), given);
  ASSERT_TRUE(r.valid());
  EXPECT_EQ(r.brightness.a, given.a);
  EXPECT_EQ(r.brightness.b, given.b);
  EXPECT_LT(translation_error(r.T_cur_ref, T_true_), 0.002);
}

TEST_F(SparseAlignTest, TexturelessImageIsRejected) {
  const ImagePyramid flat = build_pyramid(cv::Mat(480, 752, CV_8UC1, cv::Scalar(90)), 4);
  SparseAligner aligner;
  const SparseAlignResult r = aligner.align(flat, flat, cam(), *points_, T_true_);
  EXPECT_FALSE(r.valid());
  EXPECT_EQ(r.status, SparseAlignStatus::kDegenerate);
}

TEST_F(SparseAlignTest, RejectsMismatchedPyramids) {
  const ImagePyramid small = build_pyramid(cv::Mat(240, 376, CV_8UC1, cv::Scalar(0)), 4);
  const ImagePyramid three = build_pyramid(cv::Mat(480, 752, CV_8UC1, cv::Scalar(0)), 3);
  SparseAligner aligner;
  EXPECT_THROW(aligner.align(*ref_, small, cam(), *points_, T_true_), std::invalid_argument);
  EXPECT_THROW(aligner.align(*ref_, three, cam(), *points_, T_true_), std::invalid_argument);
}

}  // namespace
}  // namespace hs
