#include "mapper/schur_lm.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace hs {
namespace {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using ConstRowMajorMap = Eigen::Map<const RowMajorMatrix>;

constexpr double kMinDiagonal = 1e-6;  // Ceres' min_lm_diagonal / max_lm_diagonal
constexpr double kMaxDiagonal = 1e32;
constexpr double kInitialRadius = 1e4;  // Ceres' initial_trust_region_radius
constexpr double kMaxRadius = 1e16;
constexpr double kMinRadius = 1e-32;
constexpr double kMinRelativeDecrease = 1e-3;
constexpr double kParameterTolerance = 1e-8;

// Whitens a term's residual in place and returns the factor for its Jacobians; adds the term's
// cost. NaN when the loss cannot be handled.
double robust_scale(const ceres::LossFunction* loss, int rows, double* r, double* cost) {
  Eigen::Map<Eigen::VectorXd> f(r, rows);
  const double s = f.squaredNorm();
  if (!std::isfinite(s)) return std::nan("");
  if (loss == nullptr) {
    *cost += 0.5 * s;
    return 1.0;
  }
  double rho[3];
  loss->Evaluate(s, rho);
  if (rho[2] > 0.0 && s > 0.0) throw std::invalid_argument("SchurLm: a convex loss");
  *cost += 0.5 * rho[0];
  const double scale = std::sqrt(rho[1]);
  f *= scale;
  return scale;
}

double damping(double diagonal) {
  return std::clamp(diagonal, kMinDiagonal, kMaxDiagonal);
}

using J26 = Eigen::Matrix<double, 2, 6, Eigen::RowMajor>;
using J23 = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;
using W63 = Eigen::Matrix<double, 6, 3>;

}  // namespace

SchurLm::SchurLm(std::function<bool(const double*)> is_point) : is_point_(std::move(is_point)) {}

void SchurLm::add_block(double* x, int size, const ceres::Manifold* manifold) {
  if (has_block(x)) throw std::invalid_argument("SchurLm: a block added twice");
  Block b;
  b.x = x;
  b.size = size;
  b.tangent = manifold != nullptr ? manifold->TangentSize() : size;
  b.manifold = manifold;
  if (manifold != nullptr) b.plus_jacobian.resize(static_cast<size_t>(b.size * b.tangent));
  b.backup.resize(static_cast<size_t>(b.size));
  index_.emplace(x, static_cast<int>(blocks_.size()));
  blocks_.push_back(std::move(b));
  prepared_ = false;
}

void SchurLm::set_constant(double* x) {
  blocks_[static_cast<size_t>(index_.at(x))].constant = true;
  prepared_ = false;
}

int SchurLm::block_of(double* x, int size) {
  const auto it = index_.find(x);
  if (it != index_.end()) return it->second;
  add_block(x, size);
  return static_cast<int>(blocks_.size()) - 1;
}

int SchurLm::add_term(const ceres::CostFunction* cost, const ceres::LossFunction* loss,
                      std::initializer_list<double*> blocks) {
  const std::vector<int32_t>& sizes = cost->parameter_block_sizes();
  if (sizes.size() != blocks.size())
    throw std::invalid_argument("SchurLm: a term's block count differs from its cost's");
  Term t;
  t.cost = cost;
  t.loss = loss;
  t.first = static_cast<int>(slot_block_.size());
  t.count = static_cast<int>(blocks.size());
  t.rows = cost->num_residuals();
  size_t s = 0;
  for (double* x : blocks) {
    slot_block_.push_back(block_of(x, sizes[s++]));
    slot_param_.push_back(x);
  }
  terms_.push_back(t);
  ++num_active_;
  prepared_ = false;
  return static_cast<int>(terms_.size()) - 1;
}

void SchurLm::remove_term(int id) {
  Term& t = terms_.at(static_cast<size_t>(id));
  if (t.active) --num_active_;
  t.active = false;
}

// The layout of the reduced system, of the Jacobians and of the W blocks.
void SchurLm::prepare() {
  points_.clear();
  reduced_size_ = 0;
  for (Block& b : blocks_) {
    b.offset = b.point = -1;
    if (b.constant) continue;
    if (is_point_(b.x)) {
      if (b.size != 3 || b.manifold != nullptr)
        throw std::invalid_argument("SchurLm: a point block must be 3 plain doubles");
      b.point = static_cast<int>(points_.size());
      points_.emplace_back();
    } else {
      b.offset = reduced_size_;
      reduced_size_ += b.tangent;
    }
  }
  slot_w_at_.assign(slot_block_.size(), 0);
  size_t residual_size = 0, w_size = 0, ambient = 0, tangent = 0;
  for (Term& t : terms_) {
    t.residual_at = residual_size;
    residual_size += static_cast<size_t>(t.rows);
    t.point = t.point_slot = t.pose_slot = -1;
    size_t ambient_size = 0, tangent_size = 0;
    for (int s = 0; s < t.count; ++s) {
      const Block& b = block_at(t, s);
      ambient_size += static_cast<size_t>(t.rows * b.size);
      tangent_size += static_cast<size_t>(t.rows * b.tangent);
      if (b.point < 0) continue;
      if (t.point >= 0) throw std::invalid_argument("SchurLm: a term touches two free points");
      t.point = b.point;
      t.point_slot = s;
    }
    ambient = std::max(ambient, ambient_size);
    tangent = std::max(tangent, tangent_size);
    if (t.point < 0) continue;
    PointRows& p = points_[static_cast<size_t>(t.point)];
    int reduced = 0, pose_slot = -1;
    for (int s = 0; s < t.count; ++s) {
      const Block& b = block_at(t, s);
      if (b.offset < 0) continue;
      ++reduced;
      pose_slot = b.tangent == 6 ? s : -1;
      auto it = std::find_if(p.frames.begin(), p.frames.end(),
                             [&](const PointFrame& f) { return f.offset == b.offset; });
      if (it == p.frames.end()) {
        p.frames.push_back(PointFrame{b.offset, b.tangent, w_size});
        w_size += static_cast<size_t>(3 * b.tangent);
        it = p.frames.end() - 1;
      }
      slot_w_at_[static_cast<size_t>(t.first + s)] = it->w_at;
    }
    if (t.rows == 2 && reduced == 1 && pose_slot >= 0) t.pose_slot = pose_slot;
  }
  residuals_.resize(residual_size);
  candidate_residuals_.resize(residual_size);
  w_.resize(w_size);
  ambient_.resize(ambient);
  tangent_.resize(tangent);
  prepared_ = true;
}

SchurLmSummary SchurLm::solve(const SchurLmOptions& options) {
  if (!prepared_) prepare();
  SchurLmSummary summary;
  double cost = 0.0;
  if (!linearise(&cost)) return summary;
  summary.usable = true;
  summary.initial_cost = summary.final_cost = cost;
  double radius = kInitialRadius, decrease_factor = 2.0;
  Eigen::VectorXd dx_frames, dx_points;
  for (int it = 0; it < options.max_iterations; ++it) {
    if (options.keep_going && !options.keep_going()) break;
    solve_step(1.0 / radius, &dx_frames, &dx_points);
    const double model_decrease = predicted_decrease(dx_frames, dx_points);
    const double step_norm2 = dx_frames.squaredNorm() + dx_points.squaredNorm();
    double x_norm2 = 0.0;
    for (Block& b : blocks_) {
      if (!b.free()) continue;
      std::copy(b.x, b.x + b.size, b.backup.begin());
      x_norm2 += Eigen::Map<const Eigen::VectorXd>(b.x, b.size).squaredNorm();
    }
    if (std::sqrt(step_norm2) <= kParameterTolerance * (std::sqrt(x_norm2) + kParameterTolerance))
      break;
    double new_cost = 0.0;
    const bool valid = std::isfinite(model_decrease) && apply_step(dx_frames, dx_points) &&
                       evaluate_cost(&new_cost);
    const double decrease = cost - new_cost;
    const bool good =
        valid && model_decrease > 0.0 && decrease / model_decrease > kMinRelativeDecrease;
    if (!good) {
      restore();
      ++summary.unsuccessful_steps;
      radius /= decrease_factor;
      decrease_factor *= 2.0;
      if (radius < kMinRadius) break;
      continue;
    }
    ++summary.successful_steps;
    const double rho = decrease / model_decrease;
    radius = std::min(kMaxRadius, radius / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3)));
    decrease_factor = 2.0;
    const bool converged = decrease <= options.function_tolerance * cost;
    summary.final_cost = new_cost;
    if (converged || it + 1 == options.max_iterations) break;
    if (!linearise(&cost)) break;  // cannot happen: new_cost was evaluated at this point
  }
  return summary;
}

// The normal equations' pieces at the current x: H and g of the reduced blocks, per point H, g
// and W, from each term's whitened residual and tangent Jacobians as soon as they are
// evaluated (the Jacobians are not kept: predicted_decrease() needs only H and W).
bool SchurLm::linearise(double* cost) {
  for (Block& b : blocks_) {
    if (b.manifold == nullptr || b.constant) continue;
    b.manifold->PlusJacobian(b.x, b.plus_jacobian.data());
    find_selection(b);
  }
  H_.setZero(reduced_size_, reduced_size_);
  g_.setZero(reduced_size_);
  std::fill(w_.begin(), w_.end(), 0.0);
  for (PointRows& p : points_) {
    p.H.setZero();
    p.g.setZero();
  }
  *cost = 0.0;
  for (const Term& t : terms_) {
    if (!t.active) continue;
    ambient_ptrs_.assign(static_cast<size_t>(t.count), nullptr);
    tangent_ptrs_.assign(static_cast<size_t>(t.count), nullptr);
    size_t at = 0, tangent_at = 0;
    for (int s = 0; s < t.count; ++s) {
      const Block& b = block_at(t, s);
      if (b.constant) continue;
      ambient_ptrs_[static_cast<size_t>(s)] = ambient_.data() + at;
      tangent_ptrs_[static_cast<size_t>(s)] = tangent_.data() + tangent_at;
      at += static_cast<size_t>(t.rows * b.size);
      tangent_at += static_cast<size_t>(t.rows * b.tangent);
    }
    double* r = residuals_.data() + t.residual_at;
    const double* const* params = slot_param_.data() + t.first;
    if (!t.cost->Evaluate(params, r, ambient_ptrs_.data())) return false;
    const double scale = robust_scale(t.loss, t.rows, r, cost);
    if (!std::isfinite(scale)) return false;
    for (int s = 0; s < t.count; ++s) {
      const Block& b = block_at(t, s);
      if (b.constant) continue;
      const double* J_ambient = ambient_ptrs_[static_cast<size_t>(s)];
      double* J = tangent_ptrs_[static_cast<size_t>(s)];
      if (!b.selected.empty()) {
        for (int row = 0; row < t.rows; ++row) {
          for (int c = 0; c < b.tangent; ++c)
            J[row * b.tangent + c] = scale * J_ambient[row * b.size + b.selected[c]];
        }
      } else if (t.rows == 2 && b.size == 3 && b.manifold == nullptr) {
        Eigen::Map<J23> J_tangent(J);
        J_tangent = scale * Eigen::Map<const J23>(J_ambient);
      } else if (b.manifold == nullptr) {
        RowMajorMap(J, t.rows, b.tangent) = scale * ConstRowMajorMap(J_ambient, t.rows, b.size);
      } else {
        RowMajorMap(J, t.rows, b.tangent).noalias() =
            scale * ConstRowMajorMap(J_ambient, t.rows, b.size) *
            ConstRowMajorMap(b.plus_jacobian.data(), b.size, b.tangent);
      }
    }
    if (t.pose_slot >= 0) {
      accumulate_reprojection(t);
    } else {
      accumulate(t);
    }
  }
  return true;
}

// A manifold whose PlusJacobian picks ambient coordinates (as mapper/pose_manifold.h's) turns
// Jacobians into the tangent space by a copy instead of a product.
void SchurLm::find_selection(Block& b) {
  b.selected.assign(static_cast<size_t>(b.tangent), -1);
  for (int c = 0; c < b.tangent; ++c) {
    for (int row = 0; row < b.size; ++row) {
      const double v = b.plus_jacobian[static_cast<size_t>(row * b.tangent + c)];
      if (v == 0.0) continue;
      if (v != 1.0 || b.selected[static_cast<size_t>(c)] >= 0) {
        b.selected.clear();
        return;
      }
      b.selected[static_cast<size_t>(c)] = row;
    }
    if (b.selected[static_cast<size_t>(c)] < 0) {
      b.selected.clear();
      return;
    }
  }
}

void SchurLm::accumulate(const Term& t) {
  const Eigen::Map<const Eigen::VectorXd> r(residuals_.data() + t.residual_at, t.rows);
  const auto J = [&](int slot) {
    return ConstRowMajorMap(tangent_ptrs_[static_cast<size_t>(slot)], t.rows,
                            block_at(t, slot).tangent);
  };
  for (int a = 0; a < t.count; ++a) {
    const Block& ba = block_at(t, a);
    if (ba.offset < 0) continue;
    g_.segment(ba.offset, ba.tangent).noalias() += J(a).transpose() * r;
    for (int b = 0; b < t.count; ++b) {
      const Block& bb = block_at(t, b);
      if (bb.offset < 0) continue;
      H_.block(ba.offset, bb.offset, ba.tangent, bb.tangent).noalias() += J(a).transpose() * J(b);
    }
  }
  if (t.point < 0) return;
  PointRows& p = points_[static_cast<size_t>(t.point)];
  const auto Jp = J(t.point_slot);
  p.H.noalias() += Jp.transpose() * Jp;
  p.g.noalias() += Jp.transpose() * r;
  for (int a = 0; a < t.count; ++a) {
    const Block& ba = block_at(t, a);
    if (ba.offset < 0) continue;
    w(slot_w_at_[static_cast<size_t>(t.first + a)], ba.tangent).noalias() += J(a).transpose() * Jp;
  }
}

// The bulk of the terms, in fixed sizes.
void SchurLm::accumulate_reprojection(const Term& t) {
  const Block& b = block_at(t, t.pose_slot);
  const Eigen::Map<const Eigen::Vector2d> r(residuals_.data() + t.residual_at);
  const Eigen::Map<const J26> Jf(tangent_ptrs_[static_cast<size_t>(t.pose_slot)]);
  const Eigen::Map<const J23> Jp(tangent_ptrs_[static_cast<size_t>(t.point_slot)]);
  g_.segment<6>(b.offset).noalias() += Jf.transpose() * r;
  H_.block<6, 6>(b.offset, b.offset).noalias() += Jf.transpose() * Jf;
  PointRows& p = points_[static_cast<size_t>(t.point)];
  p.H.noalias() += Jp.transpose() * Jp;
  p.g.noalias() += Jp.transpose() * r;
  Eigen::Map<W63>(w_.data() + slot_w_at_[static_cast<size_t>(t.first + t.pose_slot)]).noalias() +=
      Jf.transpose() * Jp;
}

// (J'J + lambda D) dx = -J'f with the points eliminated. Only the lower triangle of the
// reduced system is formed: the LDLT reads no other.
void SchurLm::solve_step(double lambda, Eigen::VectorXd* dx_frames, Eigen::VectorXd* dx_points) {
  S_ = H_;
  for (int i = 0; i < reduced_size_; ++i) S_(i, i) += lambda * damping(H_(i, i));
  rhs_ = -g_;
  for (PointRows& p : points_) {
    Eigen::Matrix3d A = p.H;
    for (int i = 0; i < 3; ++i) A(i, i) += lambda * damping(p.H(i, i));
    p.A_inv = A.inverse();
    for (const PointFrame& fa : p.frames) {
      if (fa.tangent != 6) {
        WA_.noalias() = w(fa.w_at, fa.tangent) * p.A_inv;
        for (const PointFrame& fb : p.frames) {
          if (fb.offset > fa.offset) continue;
          S_.block(fa.offset, fb.offset, fa.tangent, fb.tangent).noalias() -=
              WA_ * w(fb.w_at, fb.tangent).transpose();
        }
        rhs_.segment(fa.offset, fa.tangent).noalias() += WA_ * p.g;
        continue;
      }
      // Keyframe poses, the bulk: in fixed sizes.
      const W63 WA = Eigen::Map<const W63>(w_.data() + fa.w_at) * p.A_inv;
      for (const PointFrame& fb : p.frames) {
        if (fb.offset > fa.offset) continue;
        if (fb.tangent == 6) {
          S_.block<6, 6>(fa.offset, fb.offset).noalias() -=
              WA * Eigen::Map<const W63>(w_.data() + fb.w_at).transpose();
        } else {
          S_.block(fa.offset, fb.offset, 6, fb.tangent).noalias() -=
              WA * w(fb.w_at, fb.tangent).transpose();
        }
      }
      rhs_.segment<6>(fa.offset).noalias() += WA * p.g;
    }
  }
  ldlt_.compute(S_);
  *dx_frames = ldlt_.solve(rhs_);
  dx_points->resize(3 * static_cast<Eigen::Index>(points_.size()));
  for (size_t k = 0; k < points_.size(); ++k) {
    const PointRows& p = points_[k];
    Eigen::Vector3d b = p.g;
    for (const PointFrame& f : p.frames)
      b.noalias() += w(f.w_at, f.tangent).transpose() * dx_frames->segment(f.offset, f.tangent);
    dx_points->segment<3>(3 * static_cast<Eigen::Index>(k)) = -p.A_inv * b;
  }
}

// -(g'dx + |J dx|^2 / 2): the linearised cost decrease, as Ceres' model_cost_change, with
// |J dx|^2 = dx_f' H dx_f + 2 dx_f' W dx_p + dx_p' H_p dx_p.
double SchurLm::predicted_decrease(const Eigen::VectorXd& dx_frames,
                                   const Eigen::VectorXd& dx_points) const {
  double jdx2 = dx_frames.dot(H_ * dx_frames);
  double decrease = -g_.dot(dx_frames);
  for (size_t k = 0; k < points_.size(); ++k) {
    const PointRows& p = points_[k];
    const auto dx_p = dx_points.segment<3>(3 * static_cast<Eigen::Index>(k));
    decrease -= p.g.dot(dx_p);
    Eigen::Vector3d H_dx = p.H * dx_p;
    for (const PointFrame& f : p.frames)
      H_dx.noalias() +=
          2.0 * w(f.w_at, f.tangent).transpose() * dx_frames.segment(f.offset, f.tangent);
    jdx2 += dx_p.dot(H_dx);
  }
  return decrease - 0.5 * jdx2;
}

Eigen::Map<const Eigen::VectorXd> SchurLm::step_of(const Block& b, const Eigen::VectorXd& dx_frames,
                                                   const Eigen::VectorXd& dx_points) const {
  return b.point >= 0 ? Eigen::Map<const Eigen::VectorXd>(dx_points.data() + 3 * b.point, 3)
                      : Eigen::Map<const Eigen::VectorXd>(dx_frames.data() + b.offset, b.tangent);
}

// x <- Plus(x, dx) for every free block (their values were saved in backup).
bool SchurLm::apply_step(const Eigen::VectorXd& dx_frames, const Eigen::VectorXd& dx_points) {
  for (Block& b : blocks_) {
    if (b.constant) continue;
    const Eigen::Map<const Eigen::VectorXd> dx = step_of(b, dx_frames, dx_points);
    if (b.manifold == nullptr) {
      Eigen::Map<Eigen::VectorXd>(b.x, b.size) += dx;
    } else if (!b.manifold->Plus(b.backup.data(), dx.data(), b.x)) {
      return false;
    }
  }
  return true;
}

void SchurLm::restore() {
  for (Block& b : blocks_) {
    if (b.free()) std::copy(b.backup.begin(), b.backup.end(), b.x);
  }
}

bool SchurLm::evaluate_cost(double* cost) {
  *cost = 0.0;
  for (const Term& t : terms_) {
    if (!t.active) continue;
    double* r = candidate_residuals_.data() + t.residual_at;
    if (!t.cost->Evaluate(slot_param_.data() + t.first, r, nullptr)) return false;
    if (!std::isfinite(robust_scale(t.loss, t.rows, r, cost))) return false;
  }
  return std::isfinite(*cost);
}

}  // namespace hs
