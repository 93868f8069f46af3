#include "tracker/direct_align.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/imu/so3.h"
#include "tracker/direct_sampling.h"

namespace hs {

namespace {

// 4x4 patch centred on the point (offsets -1.5 .. 1.5). Centred rather than at integer offsets
// from a keypoint: both patches are then interpolated, and smoothed alike, which measured a
// smaller brightness-gain bias and residual on synthetic scenes.
constexpr int kPatch = 4;
constexpr int kArea = kPatch * kPatch;
constexpr double kFirst = 0.5 * (kPatch - 1);  // minus the first offset
constexpr int kGrid = kPatch + 2;  // reference samples incl. the border for central differences

using Matrix8d = Eigen::Matrix<double, 8, 8>;
using Vector8d = Eigen::Matrix<double, 8, 1>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

double huber_cost(double r, double k) {
  const double ar = std::abs(r);
  return ar <= k ? 0.5 * r * r : k * (ar - 0.5 * k);
}

// Solves (H + lambda * diag(H)) x = -g with Jacobi scaling; false when (near) singular.
bool solve_damped(const Matrix8d& H, const Vector8d& g, double lambda, Vector8d* x) {
  const Vector8d d = H.diagonal();
  if (!(d.minCoeff() > 0.0)) return false;
  const Vector8d s = d.cwiseSqrt().cwiseInverse();
  Matrix8d Hs = s.asDiagonal() * H * s.asDiagonal();
  Hs.diagonal().array() += lambda;
  const Eigen::LDLT<Matrix8d> ldlt(Hs);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || ldlt.rcond() < 1e-12) return false;
  *x = -(s.asDiagonal() * ldlt.solve(s.asDiagonal() * g));
  return x->allFinite();
}

// Adds sign * M^T S M to H, where S is a patch's sum of q q^T over the per-pixel basis
// q = (gx, gy, I_ref, 1) and M maps that basis to (xi, a, b) up to the brightness factors:
// rows (A.row(0), 0, 0), (A.row(1), 0, 0), (0, 1, 0), (0, 0, 1).
void add_patch(const Eigen::Matrix4f& S, const Eigen::Matrix<double, 2, 6>& A, double sign,
               Matrix8d* H) {
  const Eigen::Matrix4d Sd = sign * S.cast<double>();
  H->topLeftCorner<6, 6>().noalias() += A.transpose() * (Sd.topLeftCorner<2, 2>() * A);
  const Vector6d ha = A.transpose() * Sd.block<2, 1>(0, 2);
  const Vector6d hb = A.transpose() * Sd.block<2, 1>(0, 3);
  H->block<6, 1>(0, 6) += ha;
  H->block<1, 6>(6, 0) += ha.transpose();
  H->block<6, 1>(0, 7) += hb;
  H->block<1, 6>(7, 0) += hb.transpose();
  H->bottomRightCorner<2, 2>() += Sd.bottomRightCorner<2, 2>();
}

}  // namespace

const char* to_string(SparseAlignStatus status) {
  switch (status) {
    case SparseAlignStatus::kOk:
      return "ok";
    case SparseAlignStatus::kTooFewPoints:
      return "too few points inside both images";
    case SparseAlignStatus::kTooFewInliers:
      return "too few photometric inliers";
    case SparseAlignStatus::kDegenerate:
      return "degenerate normal equations";
  }
  return "unknown";
}

// Normal equations in (xi, a, b), normalised by the residual scale squared.
struct SparseAligner::Normal {
  Matrix8d H = Matrix8d::Zero();
  Vector8d g = Vector8d::Zero();
};

struct SparseAligner::State {
  Eigen::Isometry3d T_cur_ref = Eigen::Isometry3d::Identity();
  double a = 0.0, b = 0.0;
};

SparseAligner::SparseAligner(const SparseAlignOptions& options) : options_(options) {}

void SparseAligner::prepare_level(const cv::Mat& ref_img, int level) {
  const double s = 1.0 / static_cast<double>(1 << level);
  level_H_.setZero();
  for (size_t i = 0; i < uv0_.size(); ++i) {
    LevelPoint& lp = level_points_[i];
    const Eigen::Vector2d uv = direct::to_level(uv0_[i], level);
    direct::Grid grid;
    lp.valid =
        direct::make_grid(ref_img, uv.x() - kFirst - 1.0, uv.y() - kFirst - 1.0, kGrid, &grid);
    if (!lp.valid) continue;
    float v[kGrid * kGrid];
    direct::sample_grid<kGrid>(ref_img, grid, v);
    lp.S.setZero();
    for (int j = 0; j < kPatch; ++j) {
      for (int i = 0; i < kPatch; ++i) {
        const float* c = v + (j + 1) * kGrid + (i + 1);
        Eigen::Vector4f& q = lp.q[j * kPatch + i];
        q << 0.5f * (c[1] - c[-1]), 0.5f * (c[kGrid] - c[-kGrid]), c[0], 1.f;
        lp.S.noalias() += q * q.transpose();
      }
    }
    lp.A = s * jac0_[i];
    add_patch(lp.S, lp.A, 1.0, &level_H_);
  }
}

// Samples the current image for every usable reference patch at `state`.
void SparseAligner::compute_residuals(const cv::Mat& cur_img, int level, const State& state,
                                      Residuals* res) const {
  const PinholeRadtan& cam = *cam_;
  const std::vector<Eigen::Vector3d>& pts = *p_ref_;
  const Eigen::Matrix3d R = state.T_cur_ref.linear();
  const Eigen::Vector3d t = state.T_cur_ref.translation();
  const float c = static_cast<float>(std::exp(state.a));
  const float b = static_cast<float>(state.b);
  res->num_valid = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    res->rms[i] = -1.f;
    const LevelPoint& lp = level_points_[i];
    const Eigen::Vector3d p = R * pts[i] + t;
    if (!lp.valid || !(p.z() > 0.0)) continue;
    const Eigen::Vector2d uv = direct::to_level(cam.project(p), level);
    direct::Grid grid;
    if (!direct::make_grid(cur_img, uv.x() - kFirst, uv.y() - kFirst, kPatch, &grid)) continue;
    float* r = res->r.data() + i * kArea;
    direct::sample_grid<kPatch>(cur_img, grid, r);
    float ss = 0.f;
    for (int j = 0; j < kArea; ++j) {
      r[j] -= c * lp.q[j][2] + b;
      ss += r[j] * r[j];
    }
    res->rms[i] = std::sqrt(ss / kArea);
    ++res->num_valid;
  }
}

// Median patch RMS residual (floored): the scale of a level's robust weights.
double SparseAligner::median_scale(const Residuals& res) {
  sort_buffer_.clear();
  for (const float r : res.rms) {
    if (r >= 0.f) sort_buffer_.push_back(r);
  }
  if (sort_buffer_.empty()) return options_.min_residual_scale;
  const auto mid = sort_buffer_.begin() + sort_buffer_.size() / 2;
  std::nth_element(sort_buffer_.begin(), mid, sort_buffer_.end());
  return std::max(options_.min_residual_scale, static_cast<double>(*mid));
}

// Robust cost of `res` (normalised by scale^2) and the normal equations. Patches that left the
// current image or are gated as outliers cost a constant, so that costs stay comparable within
// a level.
double SparseAligner::accumulate(const State& state, const Residuals& res, double scale,
                                 Normal* normal) const {
  const double huber_k = options_.huber_k * scale;
  const float k = static_cast<float>(huber_k);
  const float gate = static_cast<float>(options_.outlier_factor * scale);
  const double penalty = kArea * huber_cost(gate, huber_k);
  // Unweighted normal equations of every reference patch; patches left out or down-weighted
  // here are subtracted (rare, so cheaper than summing the rest).
  Matrix8d H = level_H_;
  Vector6d gp = Vector6d::Zero();
  double ga = 0.0, gb = 0.0;
  double cost = 0.0;
  for (size_t i = 0; i < level_points_.size(); ++i) {
    const LevelPoint& lp = level_points_[i];
    if (!lp.valid) continue;
    if (!(res.rms[i] >= 0.f && res.rms[i] <= gate)) {  // out of the image or an outlier
      cost += penalty;
      add_patch(lp.S, lp.A, -1.0, &H);
      continue;
    }
    // Gradient in the per-pixel basis q = (gx, gy, I_ref, 1), and the Hessian part lost to
    // Huber weights below 1.
    const float* r = res.r.data() + i * kArea;
    Eigen::Vector4f g4 = Eigen::Vector4f::Zero();
    Eigen::Matrix4f S_lost = Eigen::Matrix4f::Zero();
    bool lost = false;
    float point_cost = 0.f;
    for (int j = 0; j < kArea; ++j) {
      const float ar = std::abs(r[j]);
      if (ar <= k) {
        point_cost += 0.5f * r[j] * r[j];
        g4.noalias() += r[j] * lp.q[j];
      } else {
        const float w = k / ar;
        point_cost += k * (ar - 0.5f * k);
        g4.noalias() += (w * r[j]) * lp.q[j];
        S_lost.noalias() += ((1.f - w) * lp.q[j]) * lp.q[j].transpose();
        lost = true;
      }
    }
    cost += point_cost;
    if (lost) add_patch(S_lost, lp.A, -1.0, &H);
    gp.noalias() += lp.A.transpose() * g4.head<2>().cast<double>();
    ga += g4[2];
    gb += g4[3];
  }
  const double inv_s2 = 1.0 / (scale * scale);
  cost *= inv_s2;
  // Jacobian per pixel: -D * ((gx, gy) * A, I_ref, 1) with D = diag(c, ..., c, 1).
  Vector8d D = Vector8d::Constant(std::exp(state.a));
  D[7] = 1.0;
  normal->H = inv_s2 * (D.asDiagonal() * H * D.asDiagonal());
  normal->g << gp, ga, gb;
  normal->g = -inv_s2 * D.cwiseProduct(normal->g);
  if (prior_) {
    const Eigen::Matrix3d R = state.T_cur_ref.linear();
    const Eigen::Vector3d e = so3::log(Eigen::Matrix3d(prior_->R_cur_ref.transpose() * R));
    cost += 0.5 * e.dot(prior_->information * e);
    // R is updated as R * Exp(-dtheta): de/d(dtheta) = -Jr^-1(e).
    const Eigen::Matrix3d J = -so3::right_jacobian_inverse(e);
    normal->H.block<3, 3>(3, 3) += J.transpose() * prior_->information * J;
    normal->g.segment<3>(3) += J.transpose() * (prior_->information * e);
  }
  if (!options_.estimate_affine) {
    // Keep a, b: decouple them with unit diagonal and zero gradient.
    normal->H.block<8, 2>(0, 6).setZero();
    normal->H.block<2, 8>(6, 0).setZero();
    normal->H(6, 6) = normal->H(7, 7) = 1.0;
    normal->g.tail<2>().setZero();
  }
  return cost;
}

SparseAlignResult SparseAligner::align(const ImagePyramid& ref, const ImagePyramid& cur,
                                       const PinholeRadtan& cam,
                                       const std::vector<Eigen::Vector3d>& p_ref,
                                       const Eigen::Isometry3d& T_cur_ref_init,
                                       const AffineBrightness& brightness_init,
                                       const RotationPrior* prior) {
  if (ref.num_levels() < 1 || ref.num_levels() != cur.num_levels())
    throw std::invalid_argument("SparseAligner: pyramids need the same, non-zero level count");
  if (ref.levels[0].cols != cam.width || ref.levels[0].rows != cam.height ||
      cur.levels[0].size() != ref.levels[0].size())
    throw std::invalid_argument("SparseAligner: image size differs from the camera's");

  const size_t n = p_ref.size();
  cam_ = &cam;
  p_ref_ = &p_ref;
  prior_ = prior;
  uv0_.resize(n);
  jac0_.resize(n);
  level_points_.resize(n);
  for (Residuals* res : {&residuals_, &candidate_residuals_}) {
    res->r.resize(n * kArea);
    res->rms.resize(n);
  }
  sort_buffer_.reserve(n);

  // Reference pixels and d(uv)/d(xi) at level 0, with p -> p + dt + dtheta x p.
  double inv_depth_sum = 0.0;
  int depth_count = 0;
  for (size_t i = 0; i < n; ++i) {
    Eigen::Matrix<double, 2, 3> J;
    if (cam.project(p_ref[i], &uv0_[i], &J)) {
      jac0_[i] << J, -J * so3::hat(p_ref[i]);
      inv_depth_sum += 1.0 / p_ref[i].z();
      ++depth_count;
    } else {
      uv0_[i].setConstant(std::numeric_limits<double>::quiet_NaN());  // never valid
    }
  }
  const double mean_inv_depth = depth_count > 0 ? inv_depth_sum / depth_count : 0.0;

  SparseAlignResult result;
  State state;
  state.T_cur_ref = T_cur_ref_init;
  state.a = brightness_init.a;
  state.b = brightness_init.b;
  const int coarsest = std::min(options_.coarsest_level, ref.num_levels() - 1);
  const int finest = std::clamp(options_.finest_level, 0, coarsest);
  Normal normal, candidate_normal;
  double scale = options_.min_residual_scale;
  bool degenerate = false;
  for (int level = coarsest; level >= finest; --level) {
    const bool last = level == finest;
    prepare_level(ref.levels[level], level);
    const cv::Mat& cur_img = cur.levels[level];
    compute_residuals(cur_img, level, state, &residuals_);
    scale = median_scale(residuals_);
    double cost = accumulate(state, residuals_, scale, &normal);
    ++result.iterations;
    degenerate = false;
    result.converged = false;
    if (residuals_.num_valid < options_.min_points) continue;  // too few here: try the next
    const double step_scale = cam.fx / static_cast<double>(1 << level);  // pixels per radian
    // Coarse levels only need to land within the capture range of the next one.
    const double converged_px =
        options_.convergence_px * static_cast<double>(1 << (level - finest));
    double lambda = 0.0;
    for (int it = 0; it < options_.max_iterations; ++it) {
      Vector8d delta;
      if (!solve_damped(normal.H, normal.g, lambda, &delta)) {
        degenerate = true;
        break;
      }
      const Eigen::Vector3d dt = delta.head<3>(), dtheta = delta.segment<3>(3);
      // Inverse compositional: T <- T * Exp(delta)^-1.
      Eigen::Isometry3d D_inv = Eigen::Isometry3d::Identity();
      D_inv.linear() = so3::exp(-dtheta);
      D_inv.translation() = -(D_inv.linear() * dt);
      State candidate;
      candidate.T_cur_ref = state.T_cur_ref * D_inv;
      candidate.a = state.a + delta[6];
      candidate.b = state.b + delta[7];
      compute_residuals(cur_img, level, candidate, &candidate_residuals_);
      const double candidate_cost =
          accumulate(candidate, candidate_residuals_, scale, &candidate_normal);
      ++result.iterations;
      const double step_px = step_scale * (dtheta.norm() + dt.norm() * mean_inv_depth);
      const bool accepted = candidate_cost <= cost;
      if (accepted) {
        state = candidate;
        cost = candidate_cost;
        normal = candidate_normal;
        std::swap(residuals_, candidate_residuals_);
        lambda = lambda < 1e-5 ? 0.0 : 0.1 * lambda;
      } else {
        lambda = lambda == 0.0 ? 1e-4 : 10.0 * lambda;
      }
      // At the minimum: a tiny step, or a small one that does not reduce the cost (noise), or a
      // cost that no damping reduces.
      if (step_px < converged_px || (!accepted && step_px < 4.0 * converged_px) || lambda > 1e3) {
        result.converged = true;
        break;
      }
    }
    if (last) result.cost = cost;
  }

  result.T_cur_ref = state.T_cur_ref;
  result.brightness = {state.a, state.b};
  result.residual_scale = scale;
  const int num_valid = residuals_.num_valid;
  result.num_valid = num_valid;
  result.inlier.assign(n, 0);
  result.residual = residuals_.rms;
  const float gate = static_cast<float>(options_.outlier_factor * scale);
  for (size_t i = 0; i < n; ++i) {
    result.inlier[i] = result.residual[i] >= 0.f && result.residual[i] <= gate;
    result.num_inliers += result.inlier[i];
  }
  if (num_valid > 0) result.cost /= static_cast<double>(num_valid) * kArea;

  if (num_valid < options_.min_points) {
    result.status = SparseAlignStatus::kTooFewPoints;
  } else if (degenerate) {
    result.status = SparseAlignStatus::kDegenerate;
  } else if (result.num_inliers < options_.min_inlier_ratio * num_valid) {
    result.status = SparseAlignStatus::kTooFewInliers;
  } else {
    result.status = SparseAlignStatus::kOk;
    const Eigen::LDLT<Matrix8d> ldlt(normal.H);
    result.covariance = ldlt.solve(Matrix8d::Identity()).topLeftCorner<6, 6>();
  }
  cam_ = nullptr;
  p_ref_ = nullptr;
  prior_ = nullptr;
  return result;
}

}  // namespace hs
