#pragma once
// Per-point patch alignment: refines where a reference point appears in the current image by
// aligning its 8x8 reference patch (optionally warped by an affine map predicted from the
// relative pose and the point's depth) to the current image, coarse to fine, with an affine
// brightness model I_cur = gain * I_ref + bias. Gives the 2D-3D correspondences of Eq. 17 and,
// with an identity warp and the previous frame as reference, pyramidal optical flow (Eq. 9-10).
//
// Solver: Gauss-Newton on (du, dv, gain, bias) with the reference patch gradient standing in
// for the current one (inverse-compositional style), so the 4x4 Hessian is computed once per
// level; every iteration samples the current patch once. Coarse levels fit only the bias (a
// gain fitted to a misaligned patch runs away); level 0 adds the gain once the steps are small.
// Near the border, coarse levels extend the images by their border values. Pixels: level-0,
// centres at integers.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "common/calib/pinhole_radtan.h"
#include "tracker/direct_options.h"
#include "tracker/image_pyramid.h"

namespace hs {

enum class PatchAlignStatus {
  kOk,
  kOutOfImage,     // the patch left the image (or never was inside) at level 0
  kNoTexture,      // the reference patch cannot constrain the position (or singular warp)
  kNotConverged,   // iteration cap reached at level 0
  kLargeResidual,  // RMS residual above max_rms_residual
  kBadGain,        // gain outside [min_gain, max_gain]
  kTooFar,         // moved further from the guess than the search radius allows
};

const char* to_string(PatchAlignStatus status);

struct PatchAlignResult {
  Eigen::Vector2d uv_cur = Eigen::Vector2d::Zero();  // last estimate, level-0 pixel
  PatchAlignStatus status = PatchAlignStatus::kOutOfImage;
  float residual = -1.f;  // RMS grey levels at level 0 after the brightness fit (-1: none)
  float gain = 1.f, bias = 0.f;
  int iterations = 0;  // over all levels

  bool ok() const { return status == PatchAlignStatus::kOk; }
};

// d(uv_cur)/d(uv_ref) at level 0 for a patch on the plane through p_ref with normal n_ref
// (reference camera frame); a zero normal means the plane of constant reference depth
// (fronto-parallel). Identity when there is no motion. On the ground ahead or a facade along
// the road the fronto-parallel warp underestimates the stretch, and the patch follows its
// nearer, sharper part: the points seem to move more than they do.
Eigen::Matrix2d affine_warp_cur_ref(const PinholeRadtan& cam, const Eigen::Vector3d& p_ref,
                                    const Eigen::Isometry3d& T_cur_ref,
                                    const Eigen::Vector3d& n_ref = Eigen::Vector3d::Zero());

// Start level of the search: the lowest level where search_radius_px (level 0) is within the
// capture radius, clamped to [0, num_levels - 1].
int patch_start_level(double search_radius_px, int num_levels, const PatchAlignOptions& options);

// Aligns the patch around uv_ref in `ref`, seen in `cur` through A_cur_ref, starting from
// uv_guess, which is expected within search_radius_px of the truth. The pyramids may differ in
// level count; the search uses the levels both have.
PatchAlignResult align_patch(const ImagePyramid& ref, const Eigen::Vector2d& uv_ref,
                             const Eigen::Matrix2d& A_cur_ref, const ImagePyramid& cur,
                             const Eigen::Vector2d& uv_guess, double search_radius_px,
                             const PatchAlignOptions& options);

// Eq. 17 correspondences: each point is predicted at cam.project(T_cur_ref * p_ref) with the
// warp of affine_warp_cur_ref, then aligned. `results` is resized to p_ref.size().
void refine_correspondences(const ImagePyramid& ref, const ImagePyramid& cur,
                            const PinholeRadtan& cam, const std::vector<Eigen::Vector3d>& p_ref,
                            const Eigen::Isometry3d& T_cur_ref, double search_radius_px,
                            const PatchAlignOptions& options,
                            std::vector<PatchAlignResult>* results);

// Pyramidal optical flow (Eq. 9-10): tracks uv_prev from `prev` into `cur` starting from
// uv_guess (e.g. an IMU-rotation prediction, or uv_prev). Sizes must match; `results` is resized.
void track_optical_flow(const ImagePyramid& prev, const ImagePyramid& cur,
                        const std::vector<Eigen::Vector2d>& uv_prev,
                        const std::vector<Eigen::Vector2d>& uv_guess, double search_radius_px,
                        const PatchAlignOptions& options, std::vector<PatchAlignResult>* results);

}  // namespace hs
