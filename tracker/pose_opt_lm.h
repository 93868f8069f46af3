#pragma once
// Levenberg-Marquardt on a small dense problem with N-dimensional tangent steps. One
// linearisation per iteration: the system at a candidate is kept when the candidate is accepted.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>

namespace hs {

template <int N>
struct NormalEquations {
  Eigen::Matrix<double, N, N> H = Eigen::Matrix<double, N, N>::Zero();  // J^T W J
  Eigen::Matrix<double, N, 1> b = Eigen::Matrix<double, N, 1>::Zero();  // gradient J^T W r
  double cost = 0.0;
};

struct LmSettings {
  int max_iterations = 10;
  // Converged once a step is shorter than this in the metric of the Gauss-Newton Hessian,
  // sqrt(step^T H step): in standard deviations of the estimate, whatever the units.
  double min_step_sigma = 0.01;
  double initial_lambda = 1e-6;  // damping relative to the Hessian diagonal
  double max_lambda = 1e6;
};

// Minimises from *x. `linearise(const State&, NormalEquations<N>*)` returns false when the
// cost cannot be evaluated there; `retract(const State&, const Eigen::Matrix<double, N, 1>&)`
// returns the state moved by a tangent step. On return *system is the linearisation at *x.
// Returns the number of iterations that evaluated a candidate (accepted or not).
template <int N, class State, class Linearise, class Retract>
int minimise_lm(State* x, NormalEquations<N>* system, const Linearise& linearise,
                const Retract& retract, const LmSettings& settings) {
  using Vector = Eigen::Matrix<double, N, 1>;
  using Matrix = Eigen::Matrix<double, N, N>;
  if (!linearise(*x, system)) return 0;
  double lambda = settings.initial_lambda;
  NormalEquations<N> candidate_system;
  int iterations = 0;
  while (iterations < settings.max_iterations && lambda <= settings.max_lambda) {
    Matrix A = system->H;
    // Marquardt damping, with a floor so that directions the data do not constrain stay put.
    A.diagonal() += lambda * system->H.diagonal().cwiseMax(1e-9);
    const Vector step = A.ldlt().solve(-system->b);
    if (!step.allFinite()) {
      lambda *= 10.0;
      continue;
    }
    if (step.dot(system->H * step) < settings.min_step_sigma * settings.min_step_sigma) break;
    const State candidate = retract(*x, step);
    ++iterations;
    if (linearise(candidate, &candidate_system) && candidate_system.cost <= system->cost) {
      *x = candidate;
      *system = candidate_system;
      lambda = std::fmax(lambda * 0.1, 1e-12);
    } else {
      lambda *= 10.0;
    }
  }
  return iterations;
}

}  // namespace hs
