#pragma once
// Sparse image alignment (paper Eq. 16-18, SVO-style): estimates the relative pose T_cur_ref
// and an affine brightness change by minimising the photometric error of 4x4 patches around
// points with known 3D position in the reference camera, coarse to fine over the pyramids.
//
// Conventions
// - Points p_ref are in the reference camera frame; their reference pixel is cam.project(p_ref)
//   (build p_ref = depth * unproject(uv) from a keypoint so that both agree).
// - Images are the raw distorted images; `cam` maps between them and camera-frame points.
// - Brightness: I_cur(x') ~= exp(a) * I_ref(x) + b, grey levels.
// - Pose perturbation is on the right: T_cur_ref_true = T_cur_ref * Exp(xi), xi = (dt, dtheta)
//   in the reference frame (translation first), with Exp(xi) = [Exp_SO3(dtheta) | dt]. The
//   covariance refers to xi.
// - Patches are translated, not warped, between the images (fine for inter-frame motion; use
//   direct_patch.h to refine single points under larger viewpoint changes).
// - Solver: inverse compositional Gauss-Newton on the pose with Jacobians precomputed on the
//   reference patches, additive on (a, b); Levenberg-Marquardt damping when a step does not
//   reduce the cost. Robust: Huber weights on pixel residuals with a per-level scale (median
//   patch RMS at the start of the level), and patches whose RMS exceeds outlier_factor * scale
//   are dropped (outliers: occlusions, moving objects, depth edges).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "common/calib/pinhole_radtan.h"
#include "tracker/direct_options.h"
#include "tracker/image_pyramid.h"

namespace hs {

struct AffineBrightness {
  double a = 0.0;  // log gain
  double b = 0.0;  // offset, grey levels
};

// Optional prior pulling the relative rotation towards a prediction (e.g. the IMU's, Eq. 16):
// cost 0.5 * e^T * information * e with e = Log(R_cur_ref_prior^T * R_cur_ref).
struct RotationPrior {
  Eigen::Matrix3d R_cur_ref = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();  // rad^-2
};

enum class SparseAlignStatus {
  kOk,
  kTooFewPoints,   // fewer than min_points patches inside both images at the finest level
  kTooFewInliers,  // inlier ratio below min_inlier_ratio
  kDegenerate,     // the normal equations are singular (no texture, collinear points, ...)
};

const char* to_string(SparseAlignStatus status);

struct SparseAlignResult {
  Eigen::Isometry3d T_cur_ref = Eigen::Isometry3d::Identity();
  AffineBrightness brightness;
  SparseAlignStatus status = SparseAlignStatus::kTooFewPoints;
  bool converged = false;  // the finest level met the step criterion (or reached a minimum)
  int num_valid = 0;       // patches inside both images at the finest level
  int num_inliers = 0;
  int iterations = 0;  // cost evaluations over all levels
  // Robust cost per valid patch pixel at the finest level, in units of residual_scale^2.
  double cost = 0.0;
  double residual_scale = 0.0;  // grey levels, finest level
  // Per input point: inlier flag, and patch RMS residual (grey levels; -1 when not valid).
  std::vector<uint8_t> inlier;
  std::vector<float> residual;
  // Covariance of xi when valid (inverse Gauss-Newton Hessian of the photometric cost
  // normalised by residual_scale^2, plus the prior; brightness marginalised). Optimistic: patch
  // pixels are not independent.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Identity();

  bool valid() const { return status == SparseAlignStatus::kOk; }
};

// Keeps its work buffers between calls, so tracking frame after frame does not allocate in the
// iterations. Not thread-safe: one aligner per thread.
class SparseAligner {
 public:
  explicit SparseAligner(const SparseAlignOptions& options = {});

  // `ref` and `cur` must have the same number of levels and level-0 size cam.width x height.
  // Throws std::invalid_argument otherwise.
  SparseAlignResult align(const ImagePyramid& ref, const ImagePyramid& cur,
                          const PinholeRadtan& cam, const std::vector<Eigen::Vector3d>& p_ref,
                          const Eigen::Isometry3d& T_cur_ref_init,
                          const AffineBrightness& brightness_init = {},
                          const RotationPrior* prior = nullptr);

  const SparseAlignOptions& options() const { return options_; }

 private:
  // A reference patch at the current level: per pixel (gx, gy, I_ref, 1), their outer-product
  // sum (the unweighted normal equations in that basis) and d(uv)/d(xi) at this level.
  struct LevelPoint {
    Eigen::Vector4f q[16];
    Eigen::Matrix4f S;
    Eigen::Matrix<double, 2, 6> A;
    bool valid = false;
  };
  struct Normal;
  struct State;

  void prepare_level(const cv::Mat& ref_img, int level);
  // A linearisation point's residuals: kArea per patch, and the patch RMS (-1: not usable).
  struct Residuals {
    std::vector<float> r, rms;
    int num_valid = 0;
  };
  void compute_residuals(const cv::Mat& cur_img, int level, const State& state,
                         Residuals* res) const;
  double median_scale(const Residuals& res);
  double accumulate(const State& state, const Residuals& res, double scale, Normal* normal) const;

  SparseAlignOptions options_;
  const PinholeRadtan* cam_ = nullptr;
  const std::vector<Eigen::Vector3d>* p_ref_ = nullptr;
  const RotationPrior* prior_ = nullptr;
  std::vector<Eigen::Matrix<double, 2, 6>> jac0_;  // d(uv_ref level 0)/d(xi) per point
  std::vector<Eigen::Vector2d> uv0_;               // reference pixels, level 0
  std::vector<LevelPoint> level_points_;           // current level's reference patches
  // Their unweighted normal equations in (xi, a, b) without the brightness factors.
  Eigen::Matrix<double, 8, 8> level_H_;
  Residuals residuals_, candidate_residuals_;
  std::vector<float> sort_buffer_;
};

}  // namespace hs
