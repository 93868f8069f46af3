#include "mapper/schur_lm.h"

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace hs {
namespace {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using RowMajorMap = Eigen::Map<RowMajorMatrix>;
using ConstRowMajorMap = Eigen::Map<const RowMajorMatrix>;
using Matrix3Xd = Eigen::Matrix<double, Eigen::Dynamic, 3>;

constexpr double kMinDiagonal = 1e-6;  // Ceres' min_lm_diagonal / max_lm_diagonal
constexpr double kMaxDiagonal = 1e32;
constexpr double kInitialRadius = 1e4;  // Ceres' initial_trust_region_radius
constexpr double kMaxRadius = 1e16;
constexpr double kMinRadius = 1e-32;
constexpr double kMinRelativeDecrease = 1e-3;
constexpr double kParameterTolerance = 1e-8;

struct Block {
  double* x = nullptr;
  int size = 0;
  int tangent = 0;
  const ceres::Manifold* manifold = nullptr;
  bool free = false;
  int offset = -1;                    // in the reduced system (free keyframe-side blocks)
  int point = -1;                     // index of a free point block
  std::vector<double> plus_jacobian;  // size x tangent, row-major, at the current x
  std::vector<double> backup;
};

struct Term {
  const ceres::CostFunction* cost = nullptr;
  const ceres::LossFunction* loss = nullptr;
  std::vector<int> blocks;
  std::vector<const double*> params;
  std::vector<size_t> jacobian_at;  // per block: offset of its tangent Jacobian (free blocks)
  std::vector<size_t> w_at;         // per block: offset of W(point, block) (point terms)
  int rows = 0;
  int point = -1;  // free point this term touches, or -1
  int point_slot = -1;
  int pose_slot = -1;  // a reprojection-shaped term: 2 rows, this one free 6-dof block + point
  size_t residual_at = 0;
};

// W = sum of J_frame' J_point over the terms of one point and one reduced block.
struct PointFrame {
  int block = 0;
  int offset = 0;  // the block's, in the reduced system
  int tangent = 0;
  size_t w_at = 0;
};

struct PointRows {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  Eigen::Matrix3d A_inv;
  std::vector<PointFrame> frames;
};

class SchurLm {
 public:
  SchurLm(ceres::Problem& problem, const std::function<bool(const double*)>& is_point) {
    std::vector<double*> blocks;
    problem.GetParameterBlocks(&blocks);
    std::unordered_map<const double*, int> index;
    for (double* x : blocks) {
      Block b;
      b.x = x;
      b.size = problem.ParameterBlockSize(x);
      b.tangent = problem.ParameterBlockTangentSize(x);
      b.manifold = problem.GetManifold(x);
      b.free = !problem.IsParameterBlockConstant(x);
      if (b.free && is_point(x)) {
        if (b.size != 3 || b.manifold != nullptr)
          throw std::invalid_argument("solve_schur_lm: a point block must be 3 plain doubles");
        b.point = static_cast<int>(points_.size());
        points_.emplace_back();
      } else if (b.free) {
        b.offset = reduced_size_;
        reduced_size_ += b.tangent;
      }
      if (b.manifold != nullptr) b.plus_jacobian.resize(static_cast<size_t>(b.size * b.tangent));
      if (b.free) b.backup.resize(static_cast<size_t>(b.size));
      index.emplace(x, static_cast<int>(blocks_.size()));
      blocks_.push_back(std::move(b));
    }
    std::vector<ceres::ResidualBlockId> ids;
    problem.GetResidualBlocks(&ids);
    std::vector<double*> term_blocks;
    size_t jacobian_size = 0, residual_size = 0, w_size = 0;
    for (ceres::ResidualBlockId id : ids) {
      Term t;
      t.cost = problem.GetCostFunctionForResidualBlock(id);
      t.loss = problem.GetLossFunctionForResidualBlock(id);
      t.rows = t.cost->num_residuals();
      t.residual_at = residual_size;
      residual_size += static_cast<size_t>(t.rows);
      problem.GetParameterBlocksForResidualBlock(id, &term_blocks);
      for (double* x : term_blocks) {
        const int k = index.at(x);
        const Block& b = blocks_[static_cast<size_t>(k)];
        t.blocks.push_back(k);
        t.params.push_back(x);
        t.jacobian_at.push_back(jacobian_size);
        if (b.free) jacobian_size += static_cast<size_t>(t.rows * b.tangent);
        if (b.point >= 0) {
          if (t.point >= 0)
            throw std::invalid_argument("solve_schur_lm: a term touches two free points");
          t.point = b.point;
          t.point_slot = static_cast<int>(t.blocks.size()) - 1;
        }
      }
      if (t.point >= 0) {
        PointRows& p = points_[static_cast<size_t>(t.point)];
        for (const int k : t.blocks) {
          const Block& b = blocks_[static_cast<size_t>(k)];
          if (!b.free || b.point >= 0) {
            t.w_at.push_back(0);
            continue;
          }
          auto it = std::find_if(p.frames.begin(), p.frames.end(),
                                 [&](const PointFrame& f) { return f.block == k; });
          if (it == p.frames.end()) {
            p.frames.push_back(PointFrame{k, b.offset, b.tangent, w_size});
            w_size += static_cast<size_t>(3 * b.tangent);
            it = p.frames.end() - 1;
          }
          t.w_at.push_back(it->w_at);
        }
        int reduced = 0, slot = -1;
        for (size_t s = 0; s < t.blocks.size(); ++s) {
          const Block& b = blocks_[static_cast<size_t>(t.blocks[s])];
          if (b.offset < 0) continue;
          ++reduced;
          slot = b.tangent == 6 ? static_cast<int>(s) : -1;
        }
        if (t.rows == 2 && reduced == 1 && slot >= 0) t.pose_slot = slot;
      }
      terms_.push_back(std::move(t));
    }
    jacobians_.resize(jacobian_size);
    residuals_.resize(residual_size);
    candidate_residuals_.resize(residual_size);
    w_.resize(w_size);
    size_t ambient = 0;
    for (const Term& t : terms_) {
      size_t sum = 0;
      for (const int k : t.blocks) sum += static_cast<size_t>(t.rows * blocks_[k].size);
      ambient = std::max(ambient, sum);
    }
    ambient_.resize(ambient);
  }

  SchurLmSummary solve(const SchurLmOptions& options) {
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
        if (!b.free) continue;
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
      radius =
          std::min(kMaxRadius, radius / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3)));
      decrease_factor = 2.0;
      const bool converged = decrease <= options.function_tolerance * cost;
      summary.final_cost = new_cost;
      if (converged || it + 1 == options.max_iterations) break;
      if (!linearise(&cost)) break;  // cannot happen: new_cost was evaluated at this point
    }
    return summary;
  }

 private:
  // Residuals (whitened by the loss) and tangent Jacobians at the current x; the normal
  // equations' pieces: H and g of the reduced blocks, per point H, g and W.
  bool linearise(double* cost) {
    for (Block& b : blocks_) {
      if (b.manifold != nullptr && b.free) b.manifold->PlusJacobian(b.x, b.plus_jacobian.data());
    }
    *cost = 0.0;
    std::vector<double*> jacobian_ptrs;
    for (const Term& t : terms_) {
      jacobian_ptrs.assign(t.blocks.size(), nullptr);
      size_t at = 0;
      for (size_t s = 0; s < t.blocks.size(); ++s) {
        const Block& b = blocks_[static_cast<size_t>(t.blocks[s])];
        if (!b.free) continue;
        jacobian_ptrs[s] = ambient_.data() + at;
        at += static_cast<size_t>(t.rows * b.size);
      }
      double* r = residuals_.data() + t.residual_at;
      if (!t.cost->Evaluate(t.params.data(), r, jacobian_ptrs.data())) return false;
      const double scale = robust_scale(t, r, cost);
      if (!std::isfinite(scale)) return false;
      for (size_t s = 0; s < t.blocks.size(); ++s) {
        const Block& b = blocks_[static_cast<size_t>(t.blocks[s])];
        if (!b.free) continue;
        double* J = jacobians_.data() + t.jacobian_at[s];
        if (t.rows == 2 && b.size == 7 && b.tangent == 6 && b.manifold != nullptr) {
          to_tangent<2, 7, 6>(jacobian_ptrs[s], b.plus_jacobian.data(), scale, J);
        } else if (t.rows == 2 && b.size == 3 && b.manifold == nullptr) {
          using J23 = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;
          Eigen::Map<J23> J_tangent(J);
          J_tangent = scale * Eigen::Map<const J23>(jacobian_ptrs[s]);
        } else if (b.manifold == nullptr) {
          RowMajorMap(J, t.rows, b.tangent) =
              scale * ConstRowMajorMap(jacobian_ptrs[s], t.rows, b.size);
        } else {
          RowMajorMap(J, t.rows, b.tangent).noalias() =
              scale * ConstRowMajorMap(jacobian_ptrs[s], t.rows, b.size) *
              ConstRowMajorMap(b.plus_jacobian.data(), b.size, b.tangent);
        }
      }
    }
    accumulate();
    return true;
  }

  template <int R, int A, int T>
  static void to_tangent(const double* J_ambient, const double* plus_jacobian, double scale,
                         double* J) {
    using Ambient = Eigen::Matrix<double, R, A, Eigen::RowMajor>;
    using Plus = Eigen::Matrix<double, A, T, Eigen::RowMajor>;
    Eigen::Map<Eigen::Matrix<double, R, T, Eigen::RowMajor>>(J).noalias() =
        scale * Eigen::Map<const Ambient>(J_ambient) * Eigen::Map<const Plus>(plus_jacobian);
  }

  // Whitens the term's residual in place and returns the factor for its Jacobians; adds the
  // term's cost. NaN when the loss cannot be handled.
  static double robust_scale(const Term& t, double* r, double* cost) {
    Eigen::Map<Eigen::VectorXd> f(r, t.rows);
    const double s = f.squaredNorm();
    if (!std::isfinite(s)) return std::nan("");
    if (t.loss == nullptr) {
      *cost += 0.5 * s;
      return 1.0;
    }
    double rho[3];
    t.loss->Evaluate(s, rho);
    if (rho[2] > 0.0 && s > 0.0) throw std::invalid_argument("solve_schur_lm: a convex loss");
    *cost += 0.5 * rho[0];
    const double scale = std::sqrt(rho[1]);
    f *= scale;
    return scale;
  }

  void accumulate() {
    H_.setZero(reduced_size_, reduced_size_);
    g_.setZero(reduced_size_);
    std::fill(w_.begin(), w_.end(), 0.0);
    for (PointRows& p : points_) {
      p.H.setZero();
      p.g.setZero();
    }
    for (const Term& t : terms_) {
      if (t.pose_slot >= 0) {
        accumulate_reprojection(t);
        continue;
      }
      const Eigen::Map<const Eigen::VectorXd> r(residuals_.data() + t.residual_at, t.rows);
      for (size_t a = 0; a < t.blocks.size(); ++a) {
        const Block& ba = blocks_[static_cast<size_t>(t.blocks[a])];
        if (ba.offset < 0) continue;
        const auto Ja = jacobian(t, a);
        g_.segment(ba.offset, ba.tangent).noalias() += Ja.transpose() * r;
        for (size_t b = 0; b < t.blocks.size(); ++b) {
          const Block& bb = blocks_[static_cast<size_t>(t.blocks[b])];
          if (bb.offset < 0) continue;
          H_.block(ba.offset, bb.offset, ba.tangent, bb.tangent).noalias() +=
              Ja.transpose() * jacobian(t, b);
        }
      }
      if (t.point < 0) continue;
      PointRows& p = points_[static_cast<size_t>(t.point)];
      const auto Jp = jacobian(t, static_cast<size_t>(t.point_slot));
      p.H.noalias() += Jp.transpose() * Jp;
      p.g.noalias() += Jp.transpose() * r;
      for (size_t a = 0; a < t.blocks.size(); ++a) {
        const Block& ba = blocks_[static_cast<size_t>(t.blocks[a])];
        if (ba.offset < 0) continue;
        w(t.w_at[a], ba.tangent).noalias() += jacobian(t, a).transpose() * Jp;
      }
    }
  }

  // The bulk of the terms, in fixed sizes.
  void accumulate_reprojection(const Term& t) {
    const size_t slot = static_cast<size_t>(t.pose_slot);
    const Block& b = blocks_[static_cast<size_t>(t.blocks[slot])];
    const Eigen::Map<const Eigen::Vector2d> r(residuals_.data() + t.residual_at);
    const Eigen::Map<const Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> Jf(jacobians_.data() +
                                                                            t.jacobian_at[slot]);
    const Eigen::Map<const Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> Jp(
        jacobians_.data() + t.jacobian_at[static_cast<size_t>(t.point_slot)]);
    g_.segment<6>(b.offset).noalias() += Jf.transpose() * r;
    H_.block<6, 6>(b.offset, b.offset).noalias() += Jf.transpose() * Jf;
    PointRows& p = points_[static_cast<size_t>(t.point)];
    p.H.noalias() += Jp.transpose() * Jp;
    p.g.noalias() += Jp.transpose() * r;
    Eigen::Map<Eigen::Matrix<double, 6, 3>>(w_.data() + t.w_at[slot]).noalias() +=
        Jf.transpose() * Jp;
  }

  RowMajorMap jacobian(const Term& t, size_t slot) {
    const Block& b = blocks_[static_cast<size_t>(t.blocks[slot])];
    return RowMajorMap(jacobians_.data() + t.jacobian_at[slot], t.rows, b.tangent);
  }
  Eigen::Map<Matrix3Xd> w(size_t at, int rows) {
    return Eigen::Map<Matrix3Xd>(w_.data() + at, rows, 3);
  }
  Eigen::Map<Eigen::Matrix<double, 6, 3>> w6(size_t at) {
    return Eigen::Map<Eigen::Matrix<double, 6, 3>>(w_.data() + at);
  }

  static double damping(double diagonal) {
    return std::clamp(diagonal, kMinDiagonal, kMaxDiagonal);
  }

  // (J'J + lambda D) dx = -J'f with the points eliminated. Only the lower triangle of the
  // reduced system is formed: the LDLT reads no other.
  void solve_step(double lambda, Eigen::VectorXd* dx_frames, Eigen::VectorXd* dx_points) {
    S_ = H_;
    for (int i = 0; i < reduced_size_; ++i) S_(i, i) += lambda * damping(H_(i, i));
    rhs_ = -g_;
    for (PointRows& p : points_) {
      Eigen::Matrix3d A = p.H;
      for (int i = 0; i < 3; ++i) A(i, i) += lambda * damping(p.H(i, i));
      p.A_inv = A.inverse();
      for (const PointFrame& fa : p.frames) {
        const Matrix3Xd WA = w(fa.w_at, fa.tangent) * p.A_inv;  // W_a A^-1
        for (const PointFrame& fb : p.frames) {
          if (fb.offset > fa.offset) continue;
          if (fa.tangent == 6 && fb.tangent == 6) {
            S_.block<6, 6>(fa.offset, fb.offset).noalias() -=
                Eigen::Map<const Eigen::Matrix<double, 6, 3>>(WA.data()) * w6(fb.w_at).transpose();
          } else {
            S_.block(fa.offset, fb.offset, fa.tangent, fb.tangent).noalias() -=
                WA * w(fb.w_at, fb.tangent).transpose();
          }
        }
        rhs_.segment(fa.offset, fa.tangent).noalias() += WA * p.g;
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

  // -(g'dx + |J dx|^2 / 2): the linearised cost decrease, as Ceres' model_cost_change.
  double predicted_decrease(const Eigen::VectorXd& dx_frames, const Eigen::VectorXd& dx_points) {
    double decrease = -g_.dot(dx_frames);
    for (size_t k = 0; k < points_.size(); ++k)
      decrease -= points_[k].g.dot(dx_points.segment<3>(3 * static_cast<Eigen::Index>(k)));
    double jdx2 = 0.0;
    Eigen::VectorXd v;
    for (const Term& t : terms_) {
      if (t.pose_slot >= 0) {
        const size_t slot = static_cast<size_t>(t.pose_slot);
        const Block& b = blocks_[static_cast<size_t>(t.blocks[slot])];
        const Eigen::Map<const Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> Jf(
            jacobians_.data() + t.jacobian_at[slot]);
        const Eigen::Map<const Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> Jp(
            jacobians_.data() + t.jacobian_at[static_cast<size_t>(t.point_slot)]);
        jdx2 += (Jf * dx_frames.segment<6>(b.offset) +
                 Jp * dx_points.segment<3>(3 * static_cast<Eigen::Index>(t.point)))
                    .squaredNorm();
        continue;
      }
      v.setZero(t.rows);
      for (size_t s = 0; s < t.blocks.size(); ++s) {
        const Block& b = blocks_[static_cast<size_t>(t.blocks[s])];
        if (!b.free) continue;
        v.noalias() += jacobian(t, s) * step_of(b, dx_frames, dx_points);
      }
      jdx2 += v.squaredNorm();
    }
    return decrease - 0.5 * jdx2;
  }

  static Eigen::Map<const Eigen::VectorXd> step_of(const Block& b, const Eigen::VectorXd& dx_frames,
                                                   const Eigen::VectorXd& dx_points) {
    return b.point >= 0 ? Eigen::Map<const Eigen::VectorXd>(dx_points.data() + 3 * b.point, 3)
                        : Eigen::Map<const Eigen::VectorXd>(dx_frames.data() + b.offset, b.tangent);
  }

  // x <- Plus(x, dx) for every free block (their values were saved in backup).
  bool apply_step(const Eigen::VectorXd& dx_frames, const Eigen::VectorXd& dx_points) {
    for (Block& b : blocks_) {
      if (!b.free) continue;
      const Eigen::Map<const Eigen::VectorXd> dx = step_of(b, dx_frames, dx_points);
      if (b.manifold == nullptr) {
        Eigen::Map<Eigen::VectorXd>(b.x, b.size) += dx;
      } else if (!b.manifold->Plus(b.backup.data(), dx.data(), b.x)) {
        return false;
      }
    }
    return true;
  }

  void restore() {
    for (Block& b : blocks_) {
      if (b.free) std::copy(b.backup.begin(), b.backup.end(), b.x);
    }
  }

  bool evaluate_cost(double* cost) {
    *cost = 0.0;
    for (const Term& t : terms_) {
      double* r = candidate_residuals_.data() + t.residual_at;
      if (!t.cost->Evaluate(t.params.data(), r, nullptr)) return false;
      if (!std::isfinite(robust_scale(t, r, cost))) return false;
    }
    return std::isfinite(*cost);
  }

  std::vector<Block> blocks_;
  std::vector<Term> terms_;
  std::vector<PointRows> points_;
  int reduced_size_ = 0;
  std::vector<double> jacobians_, residuals_, candidate_residuals_, w_, ambient_;
  Eigen::MatrixXd H_, S_;
  Eigen::VectorXd g_, rhs_;
  Eigen::LDLT<Eigen::MatrixXd> ldlt_;
};

}  // namespace

SchurLmSummary solve_schur_lm(ceres::Problem& problem,
                              const std::function<bool(const double*)>& is_point,
                              const SchurLmOptions& options) {
  SchurLm solver(problem, is_point);
  return solver.solve(options);
}

}  // namespace hs
