#include "tracker/direct_patch.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "tracker/direct_sampling.h"

namespace hs {

namespace {

// 8x8 patch centred on the point (offsets -3.5 .. 3.5), see direct_align.cpp.
constexpr int kPatch = 8;
constexpr int kArea = kPatch * kPatch;
constexpr double kFirst = 0.5 * (kPatch - 1);  // minus the first offset
constexpr int kGrid = kPatch + 2;  // template samples incl. the border for central differences
constexpr double kMinGainDuringSearch = 0.1, kMaxGainDuringSearch = 10.0;
constexpr double kGainFitStepPx = 0.5;  // level pixels
using PatchArray = Eigen::Map<const Eigen::Array<float, kArea, 1>>;

// The reference patch as seen at one level of the current image. The brightness model uses the
// mean-free template, I_cur = gain * (T - mean) + offset, which keeps the normal equations well
// conditioned however bright the patch is.
struct Template {
  float value[kArea];  // T - mean
  float gx[kArea], gy[kArea];
  float mean = 0.f;
  Eigen::Matrix4d H_inv;          // of the Jacobian rows (gx, gy, -(T - mean), -1)
  Eigen::Matrix3d H_inv_no_gain;  // of the rows (gx, gy, -1): gain held fixed
};

// Samples the template for current-image level `level`. M maps level-0 current-image offsets to
// level-0 reference offsets; the reference level is picked so that the samples are ~1 pixel
// apart. With `clamp`, samples beyond the border take the border's value (the centre must be
// inside).
PatchAlignStatus make_template(const ImagePyramid& ref, const Eigen::Vector2d& uv_ref,
                               const Eigen::Matrix2d& M, int level, bool clamp, Template* tpl) {
  const double footprint = std::sqrt(std::abs(M.determinant())) * static_cast<double>(1 << level);
  if (!(footprint > 0.0) || !M.allFinite()) return PatchAlignStatus::kNoTexture;
  const int ref_level =
      std::clamp(static_cast<int>(std::lround(std::log2(footprint))), 0, ref.num_levels() - 1);
  const Eigen::Matrix2d W = M * std::ldexp(1.0, level - ref_level);
  const Eigen::Vector2d c = direct::to_level(uv_ref, ref_level);
  const cv::Mat& img = ref.levels[ref_level];
  constexpr double kLo = -kFirst - 1.0, kHi = kLo + kGrid - 1;  // grid offsets incl. border
  bool inside = true;
  for (const double sx : {kLo, kHi}) {
    for (const double sy : {kLo, kHi}) {
      const Eigen::Vector2d p = c + W * Eigen::Vector2d(sx, sy);
      inside = inside && direct::bilinear_inside(img, p.x(), p.y());
    }
  }
  if (!inside && !(clamp && direct::bilinear_inside(img, c.x(), c.y())))
    return PatchAlignStatus::kOutOfImage;
  float v[kGrid * kGrid];
  direct::Grid grid;
  if (W.isIdentity(1e-12) && direct::make_grid(img, c.x() + kLo, c.y() + kLo, kGrid, &grid)) {
    direct::sample_grid<kGrid>(img, grid, v);
  } else {
    for (int j = 0; j < kGrid; ++j) {
      Eigen::Vector2d p = c + W * Eigen::Vector2d(kLo, kLo + j);
      for (int i = 0; i < kGrid; ++i, p += W.col(0)) {
        v[j * kGrid + i] = inside ? direct::sample_bilinear(img, p.x(), p.y())
                                  : direct::sample_bilinear_clamped(img, p.x(), p.y());
      }
    }
  }
  float sum = 0.f;
  for (int j = 0; j < kPatch; ++j) {
    for (int i = 0; i < kPatch; ++i) {
      const float* s = v + (j + 1) * kGrid + (i + 1);
      const int k = j * kPatch + i;
      tpl->value[k] = s[0];
      tpl->gx[k] = 0.5f * (s[1] - s[-1]);
      tpl->gy[k] = 0.5f * (s[kGrid] - s[-kGrid]);
      sum += s[0];
    }
  }
  tpl->mean = sum / kArea;
  Eigen::Matrix4d H = Eigen::Matrix4d::Zero();
  for (int k = 0; k < kArea; ++k) {
    tpl->value[k] -= tpl->mean;
    const Eigen::Vector4d j0(tpl->gx[k], tpl->gy[k], -tpl->value[k], -1.0);
    H.noalias() += j0 * j0.transpose();
  }
  // Jacobi-scaled conditioning: rejects flat patches and edges (aperture problem).
  const Eigen::Vector4d d = H.diagonal();
  if (!(d.minCoeff() > 0.0)) return PatchAlignStatus::kNoTexture;
  const Eigen::Vector4d s = d.cwiseSqrt().cwiseInverse();
  const Eigen::LDLT<Eigen::Matrix4d> ldlt(s.asDiagonal() * H * s.asDiagonal());
  if (ldlt.info() != Eigen::Success || ldlt.rcond() < 1e-4) return PatchAlignStatus::kNoTexture;
  tpl->H_inv = s.asDiagonal() * ldlt.solve(Eigen::Matrix4d::Identity()) * s.asDiagonal();
  Eigen::Matrix3d H3;
  H3 << H.topLeftCorner<2, 2>(), H.block<2, 1>(0, 3), H.block<1, 2>(3, 0), H(3, 3);
  tpl->H_inv_no_gain = H3.inverse();
  return PatchAlignStatus::kOk;
}

}  // namespace

const char* to_string(PatchAlignStatus status) {
  switch (status) {
    case PatchAlignStatus::kOk:
      return "ok";
    case PatchAlignStatus::kOutOfImage:
      return "out of image";
    case PatchAlignStatus::kNoTexture:
      return "no texture";
    case PatchAlignStatus::kNotConverged:
      return "not converged";
    case PatchAlignStatus::kLargeResidual:
      return "large residual";
    case PatchAlignStatus::kBadGain:
      return "gain out of range";
    case PatchAlignStatus::kTooFar:
      return "too far from the guess";
  }
  return "unknown";
}

Eigen::Matrix2d affine_warp_cur_ref(const PinholeRadtan& cam, const Eigen::Vector3d& p_ref,
                                    const Eigen::Isometry3d& T_cur_ref,
                                    const Eigen::Vector3d& n_ref) {
  const Eigen::Vector3d p_cur = T_cur_ref * p_ref;
  if (!(p_ref.z() > 0.0) || !(p_cur.z() > 0.0)) return Eigen::Matrix2d::Identity();
  // Reference pixel -> normalised coordinates -> point at the same depth -> current pixel.
  const Eigen::Vector2d xy = p_ref.head<2>() / p_ref.z();
  const Eigen::Matrix2d dxy_duv =
      cam.distort_jacobian(xy).inverse() * Eigen::Vector2d(1.0 / cam.fx, 1.0 / cam.fy).asDiagonal();
  Eigen::Matrix<double, 3, 2> dr_duv = Eigen::Matrix<double, 3, 2>::Zero();  // ray (x, y, 1)
  dr_duv.topRows<2>() = dxy_duv;
  // Along the ray through the neighbouring pixel to the plane: p = lambda * r with
  // n . (p - p_ref) = 0, so dp = lambda * (I - r n^T / (n . r)) dr. Rays within ~3 deg of the
  // plane keep the fronto-parallel warp (the plane's stretch is unbounded there).
  const Eigen::Vector3d r = p_ref / p_ref.z();
  Eigen::Matrix3d project_on_plane = Eigen::Matrix3d::Identity();
  if (n_ref.squaredNorm() > 0.0 && std::abs(n_ref.dot(r)) > 0.05 * r.norm() * n_ref.norm())
    project_on_plane -= r * n_ref.transpose() / n_ref.dot(r);
  const Eigen::Matrix<double, 3, 2> dp_duv = p_ref.z() * project_on_plane * dr_duv;
  Eigen::Vector2d uv;
  Eigen::Matrix<double, 2, 3> J;
  cam.project(p_cur, &uv, &J);
  return J * T_cur_ref.linear() * dp_duv;
}

int patch_start_level(double search_radius_px, int num_levels, const PatchAlignOptions& options) {
  int level = 0;
  while (level + 1 < num_levels &&
         search_radius_px > options.capture_radius_px * static_cast<double>(1 << level)) {
    ++level;
  }
  return level;
}

PatchAlignResult align_patch(const ImagePyramid& ref, const Eigen::Vector2d& uv_ref,
                             const Eigen::Matrix2d& A_cur_ref, const ImagePyramid& cur,
                             const Eigen::Vector2d& uv_guess, double search_radius_px,
                             const PatchAlignOptions& options) {
  PatchAlignResult result;
  result.uv_cur = uv_guess;
  const int num_levels = std::min(ref.num_levels(), cur.num_levels());
  if (num_levels < 1 || !uv_guess.allFinite() || !uv_ref.allFinite()) return result;
  bool invertible = false;
  Eigen::Matrix2d M;
  A_cur_ref.computeInverseWithCheck(M, invertible);
  if (!invertible) {
    result.status = PatchAlignStatus::kNoTexture;
    return result;
  }

  const int start = patch_start_level(search_radius_px, num_levels, options);
  Template tpl;
  float gain = 1.f, offset = 0.f;  // I_cur = gain * (T - mean) + offset
  bool brightness_set = false;
  bool converged = false;
  float rms = -1.f;
  for (int level = start; level >= 0; --level) {
    const PatchAlignStatus tpl_status = make_template(ref, uv_ref, M, level, level > 0, &tpl);
    converged = false;
    if (tpl_status != PatchAlignStatus::kOk) {
      if (level > 0) continue;  // near a border at a coarse level: the finer levels may fit
      result.status = tpl_status;
      return result;
    }
    const cv::Mat& img = cur.levels[level];
    Eigen::Vector2d uv = direct::to_level(result.uv_cur, level);
    bool inside = true;
    // While the patch is misaligned the gain estimate is meaningless (and can run away), so the
    // gain is only fitted at level 0, once the steps are small; coarser levels fit the offset.
    bool fit_gain = false;
    // Coarse levels only need to land within the capture range of the next one.
    const double converged_px = options.convergence_px * static_cast<double>(1 << level);
    for (int it = 0; it < options.max_iterations; ++it) {
      direct::Grid grid;
      float I[kArea];
      if (direct::make_grid(img, uv.x() - kFirst, uv.y() - kFirst, kPatch, &grid)) {
        direct::sample_grid<kPatch>(img, grid, I);
      } else if (level > 0 && direct::bilinear_inside(img, uv.x(), uv.y())) {
        direct::sample_grid_clamped<kPatch>(img, uv.x() - kFirst, uv.y() - kFirst, I);
      } else {
        inside = false;
        break;
      }
      ++result.iterations;
      if (!brightness_set) {
        float sum = 0.f;
        for (const float x : I) sum += x;
        offset = sum / kArea;
        brightness_set = true;
      }
      // Eigen arrays: the sums are vectorised (plain loops would be serial float reductions).
      const PatchArray value(tpl.value), gx(tpl.gx), gy(tpl.gy);
      const Eigen::Array<float, kArea, 1> r = PatchArray(I) - gain * value - offset;
      const float g0 = (gx * r).sum(), g1 = (gy * r).sum(), g2 = -(value * r).sum(), g3 = -r.sum();
      rms = std::sqrt(r.square().sum() / kArea);
      // Jacobian rows (gain * gx, gain * gy, -(T - mean), -1): the Hessian is the template's
      // scaled by diag(gain, gain, 1, 1), so only the gradient is recomputed.
      Eigen::Vector4d delta = Eigen::Vector4d::Zero();
      if (fit_gain) {
        delta = -tpl.H_inv * Eigen::Vector4d(g0, g1, g2, g3);
      } else {
        const Eigen::Vector3d d3 = -tpl.H_inv_no_gain * Eigen::Vector3d(g0, g1, g3);
        delta << d3[0], d3[1], 0.0, d3[2];
      }
      const Eigen::Vector2d step = delta.head<2>() / static_cast<double>(gain);
      uv += step;
      gain += static_cast<float>(delta[2]);
      offset += static_cast<float>(delta[3]);
      if (!(gain > kMinGainDuringSearch && gain < kMaxGainDuringSearch)) {
        result.status = PatchAlignStatus::kBadGain;
        return result;
      }
      const double step2 = step.squaredNorm();
      if (step2 < converged_px * converged_px && (fit_gain || level > 0)) {
        converged = true;
        break;
      }
      fit_gain = fit_gain || (level == 0 && step2 < kGainFitStepPx * kGainFitStepPx);
    }
    if (!inside) {
      if (level > 0) continue;  // keep the estimate of the coarser level
      result.status = PatchAlignStatus::kOutOfImage;
      return result;
    }
    result.uv_cur = direct::from_level(uv, level);
  }

  result.residual = rms;
  result.gain = gain;
  result.bias = offset - gain * tpl.mean;
  if (!converged) {
    result.status = PatchAlignStatus::kNotConverged;
  } else if (rms > options.max_rms_residual) {
    result.status = PatchAlignStatus::kLargeResidual;
  } else if (gain < options.min_gain || gain > options.max_gain) {
    result.status = PatchAlignStatus::kBadGain;
  } else if ((result.uv_cur - uv_guess).norm() >
             search_radius_px + options.max_extra_displacement_px) {
    result.status = PatchAlignStatus::kTooFar;
  } else {
    result.status = PatchAlignStatus::kOk;
  }
  return result;
}

void refine_correspondences(const ImagePyramid& ref, const ImagePyramid& cur,
                            const PinholeRadtan& cam, const std::vector<Eigen::Vector3d>& p_ref,
                            const Eigen::Isometry3d& T_cur_ref, double search_radius_px,
                            const PatchAlignOptions& options,
                            std::vector<PatchAlignResult>* results) {
  results->assign(p_ref.size(), PatchAlignResult());
  for (size_t i = 0; i < p_ref.size(); ++i) {
    Eigen::Vector2d uv_ref;
    const Eigen::Vector3d p_cur = T_cur_ref * p_ref[i];
    if (!cam.project(p_ref[i], &uv_ref) || !(p_cur.z() > 0.0)) continue;  // kOutOfImage
    (*results)[i] = align_patch(ref, uv_ref, affine_warp_cur_ref(cam, p_ref[i], T_cur_ref), cur,
                                cam.project(p_cur), search_radius_px, options);
  }
}

void track_optical_flow(const ImagePyramid& prev, const ImagePyramid& cur,
                        const std::vector<Eigen::Vector2d>& uv_prev,
                        const std::vector<Eigen::Vector2d>& uv_guess, double search_radius_px,
                        const PatchAlignOptions& options, std::vector<PatchAlignResult>* results) {
  if (uv_prev.size() != uv_guess.size())
    throw std::invalid_argument("track_optical_flow: uv_prev and uv_guess differ in size");
  results->resize(uv_prev.size());
  for (size_t i = 0; i < uv_prev.size(); ++i) {
    (*results)[i] = align_patch(prev, uv_prev[i], Eigen::Matrix2d::Identity(), cur, uv_guess[i],
                                search_radius_px, options);
  }
}

}  // namespace hs
