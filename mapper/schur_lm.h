#pragma once
// Levenberg-Marquardt for a bundle adjustment held in a ceres::Problem, with the point blocks
// eliminated by Schur complement and the reduced system (keyframe blocks, gravity) solved
// dense. The problem's own cost functions, losses, manifolds and constant blocks are used as
// they are; only the solve is done here. Ceres' general machinery (program reduction, block
// sparse matrices, per-term bookkeeping and checks) costs more than the bundle adjustment's own
// arithmetic on a window of ten keyframes; this solver does only the arithmetic.
//
// Step control as Ceres' LM: (J'J + D / radius) dx = -J'f with D the clamped diagonal of J'J,
// radius from 1e4, grown on good steps and halved (then quartered...) on rejected ones; a step
// is rejected when it cannot be evaluated or lowers the cost by less than 1e-3 of the model's
// prediction. Robust losses scale each term by sqrt(rho'), as Ceres does for losses with
// rho'' <= 0 (Huber, Cauchy...); others are refused.
#include <ceres/problem.h>

#include <functional>

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

// Point blocks (size 3, no manifold) are those `is_point` says so of; every residual block may
// touch at most one non-constant point block. Throws std::invalid_argument otherwise.
SchurLmSummary solve_schur_lm(ceres::Problem& problem,
                              const std::function<bool(const double*)>& is_point,
                              const SchurLmOptions& options);

}  // namespace hs
