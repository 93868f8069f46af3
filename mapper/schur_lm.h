#pragma once
// Levenberg-Marquardt for a bundle adjustment, with the point blocks eliminated by Schur
// complement and the reduced system (keyframe blocks, gravity) solved dense. The problem is
// built as a ceres::Problem is, from Ceres cost functions, losses and manifolds, but held in
// flat arrays: Ceres' general machinery (program reduction, block sparse matrices, per-term
// bookkeeping and checks) costs more than the bundle adjustment's own arithmetic on a window of
// ten keyframes; this solver does only the arithmetic. Its structure is analysed once and kept
// across solves that only remove terms (the local BA's two rounds).
//
// Step control as Ceres' LM: (J'J + D / radius) dx = -J'f with D the clamped diagonal of J'J,
// radius from 1e4, grown on good steps and halved (then quartered...) on rejected ones; a step
// is rejected when it cannot be evaluated or lowers the cost by less than 1e-3 of the model's
// prediction. Robust losses scale each term by sqrt(rho'), as Ceres does for losses with
// rho'' <= 0 (Huber, Cauchy...); others are refused.
#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <initializer_list>
#include <unordered_map>
#include <vector>

namespace hs {

struct SchurLmOptions {
  int max_iterations = 10;           // successful and rejected steps
  double function_tolerance = 1e-6;  // stop when a step changes the cost by less than this share
  std::function<bool()> keep_going;  // checked before each iteration; empty: always
};

struct SchurLmSummary {
  bool usable = false;  // the initial point could be evaluated
  double initial_cost = 0.0;
  double final_cost = 0.0;  // 0.5 sum rho(|f|^2), as Ceres
  int successful_steps = 0;
  int unsuccessful_steps = 0;
};

class SchurLm {
 public:
  // Blocks `is_point` says so of are eliminated: 3 plain doubles, and every term may touch at
  // most one of them that is not constant (solve() throws std::invalid_argument otherwise).
  explicit SchurLm(std::function<bool(const double*)> is_point);

  // As ceres::Problem: the costs, losses and manifolds are borrowed and must outlive the
  // solver; a term's blocks not added before are added as plain vectors of the cost's sizes.
  void add_block(double* x, int size, const ceres::Manifold* manifold = nullptr);
  void set_constant(double* x);
  bool has_block(const double* x) const { return index_.count(x) > 0; }
  int add_term(const ceres::CostFunction* cost, const ceres::LossFunction* loss,
               std::initializer_list<double*> blocks);
  // Leaves term `id` (from add_term) out of later solves.
  void remove_term(int id);
  int num_terms() const { return num_active_; }

  SchurLmSummary solve(const SchurLmOptions& options);

 private:
  struct Block {
    double* x = nullptr;
    int size = 0;
    int tangent = 0;
    const ceres::Manifold* manifold = nullptr;
    bool constant = false;
    int offset = -1;                    // in the reduced system (free keyframe-side blocks)
    int point = -1;                     // index of a free point block
    std::vector<double> plus_jacobian;  // size x tangent, row-major, at the current x
    std::vector<int> selected;          // when plus_jacobian is a selection: the row of each column
    std::vector<double> backup;
    bool free() const { return !constant; }
  };
  // A term's blocks are the slots [first, first + count) of the slot arrays.
  struct Term {
    const ceres::CostFunction* cost = nullptr;
    const ceres::LossFunction* loss = nullptr;
    int first = 0;
    int count = 0;
    int rows = 0;
    bool active = true;
    int point = -1;  // free point this term touches, or -1
    int point_slot = -1;
    int pose_slot = -1;  // a reprojection-shaped term: 2 rows, this one free 6-dof block + point
    size_t residual_at = 0;
  };
  // W = sum of J_frame' J_point over the terms of one point and one reduced block.
  struct PointFrame {
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
  using RowMajorMap =
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;
  using Matrix3XdMap = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3>>;
  using ConstMatrix3XdMap = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3>>;

  int block_of(double* x, int size);
  void prepare();
  static void find_selection(Block& b);
  bool linearise(double* cost);
  void accumulate(const Term& t);
  void accumulate_reprojection(const Term& t);
  void solve_step(double lambda, Eigen::VectorXd* dx_frames, Eigen::VectorXd* dx_points);
  double predicted_decrease(const Eigen::VectorXd& dx_frames,
                            const Eigen::VectorXd& dx_points) const;
  Eigen::Map<const Eigen::VectorXd> step_of(const Block& b, const Eigen::VectorXd& dx_frames,
                                            const Eigen::VectorXd& dx_points) const;
  bool apply_step(const Eigen::VectorXd& dx_frames, const Eigen::VectorXd& dx_points);
  void restore();
  bool evaluate_cost(double* cost);
  Matrix3XdMap w(size_t at, int rows) { return Matrix3XdMap(w_.data() + at, rows, 3); }
  ConstMatrix3XdMap w(size_t at, int rows) const {
    return ConstMatrix3XdMap(w_.data() + at, rows, 3);
  }
  const Block& block_at(const Term& t, int slot) const {
    return blocks_[static_cast<size_t>(slot_block_[static_cast<size_t>(t.first + slot)])];
  }

  std::function<bool(const double*)> is_point_;
  std::unordered_map<const double*, int> index_;
  std::vector<Block> blocks_;
  std::vector<Term> terms_;
  int num_active_ = 0;
  // Per slot: block, parameter pointer and offset of W(point, block) (terms of a point).
  std::vector<int> slot_block_;
  std::vector<const double*> slot_param_;
  std::vector<size_t> slot_w_at_;
  bool prepared_ = false;
  std::vector<PointRows> points_;
  int reduced_size_ = 0;
  std::vector<double> residuals_, candidate_residuals_, w_;
  // One term's Jacobians, as its cost writes them and in its blocks' tangent spaces.
  std::vector<double> ambient_, tangent_;
  std::vector<double*> ambient_ptrs_, tangent_ptrs_;
  Eigen::MatrixXd H_, S_;
  Eigen::Matrix<double, Eigen::Dynamic, 3> WA_;  // W A^-1 of a block other than a pose
  Eigen::VectorXd g_, rhs_;
  Eigen::LDLT<Eigen::MatrixXd> ldlt_;
};

}  // namespace hs
