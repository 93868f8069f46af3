#include "tracker/pose_opt.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "common/imu/so3.h"
#include "tracker/pose_opt_inertial.h"
#include "tracker/pose_opt_lm.h"

namespace hs {
namespace {

// Current state, and the previous one in the visual-inertial mode with a free previous state.
// N = 6: pose of `current`; N = 15: all of `current`; N = 30: both.
struct JointState {
  BodyState current;
  BodyState previous;
};

template <int N>
JointState retract(const JointState& x, const Eigen::Matrix<double, N, 1>& delta) {
  JointState y = x;
  if constexpr (N == 6) {
    y.current = x.current.retracted_pose(delta);
  } else {
    y.current = x.current.retracted(delta.template head<15>());
    if constexpr (N == 30) y.previous = x.previous.retracted(delta.template tail<15>());
  }
  return y;
}

struct Terms {
  const VisualTerms& visual;
  const std::vector<PoseObservation>& observations;
  const InertialTerms* inertial;  // null in pose-only mode
};

template <int N>
bool linearise(const Terms& terms, const std::vector<bool>& active, double huber_chi2,
               const JointState& x, NormalEquations<N>* system) {
  Matrix6d H_visual;
  Vector6d b_visual;
  system->cost = terms.visual.linearise(x.current, terms.observations, active, huber_chi2,
                                        &H_visual, &b_visual);
  if constexpr (N == 6) {
    system->H = H_visual;
    system->b = b_visual;
  } else {
    Matrix30d H;
    Vector30d b;
    system->cost += terms.inertial->linearise(x.current, x.previous, &H, &b);
    system->H = H.topLeftCorner<N, N>();
    system->b = b.head<N>();
    system->H.template topLeftCorner<6, 6>() += H_visual;
    system->b.template head<6>() += b_visual;
  }
  return std::isfinite(system->cost) && system->H.allFinite() && system->b.allFinite();
}

// The robust rounds. On return `inliers` and `chi2` hold the last classification at *x, and
// *system the linearisation at *x over those inliers (for the covariance / marginalisation).
template <int N>
int robust_rounds(const Terms& terms, const PoseOptOptions& options, JointState* x,
                  std::vector<bool>* inliers, std::vector<double>* chi2,
                  NormalEquations<N>* system) {
  const std::vector<PoseObservation>& observations = terms.observations;
  inliers->resize(observations.size());
  for (size_t k = 0; k < observations.size(); ++k) (*inliers)[k] = usable(observations[k]);
  const LmSettings settings{options.iterations_per_round, options.min_step_sigma,
                            options.initial_lambda, options.max_lambda};
  int iterations = 0;
  double huber_chi2 = 0.0;
  // What *system was built with: a round with the same inliers and loss would not move.
  std::vector<bool> solved_inliers;
  double solved_huber_chi2 = -1.0;
  for (int round = 0; round < options.rounds; ++round) {
    huber_chi2 = round < options.huber_rounds ? options.chi2_threshold : 0.0;
    if (*inliers == solved_inliers && huber_chi2 == solved_huber_chi2) continue;
    const auto lin = [&](const JointState& s, NormalEquations<N>* sys) {
      return linearise<N>(terms, *inliers, huber_chi2, s, sys);
    };
    iterations += minimise_lm<N>(x, system, lin, retract<N>, settings);
    solved_inliers = *inliers;
    solved_huber_chi2 = huber_chi2;
    terms.visual.chi2(x->current, observations, chi2);
    for (size_t k = 0; k < observations.size(); ++k) {
      (*inliers)[k] = (*chi2)[k] <= options.chi2_threshold;
    }
  }
  if (*inliers != solved_inliers) linearise<N>(terms, *inliers, huber_chi2, *x, system);
  return iterations;
}

// Inverse of an information matrix; zero (unknown) when it is singular or not finite.
template <int N>
Eigen::Matrix<double, N, N> covariance_or_zero(const Eigen::Matrix<double, N, N>& information) {
  using Matrix = Eigen::Matrix<double, N, N>;
  const Eigen::LLT<Matrix> llt(information);
  if (llt.info() != Eigen::Success) return Matrix::Zero();
  const Matrix covariance = llt.solve(Matrix::Identity());
  return covariance.allFinite() ? Matrix(0.5 * (covariance + covariance.transpose()))
                                : Matrix::Zero();
}

// Information of x_j with x_i marginalised out of the joint [x_j, x_i] system.
Matrix15d marginalise_previous(const Matrix30d& H) {
  const Eigen::LDLT<Matrix15d> H_ii(H.bottomRightCorner<15, 15>());
  const Matrix15d info = H.topLeftCorner<15, 15>() -
                         H.topRightCorner<15, 15>() * H_ii.solve(H.bottomLeftCorner<15, 15>());
  return 0.5 * (info + info.transpose());
}

// Inlier statistics and the failure check of Algorithm 1.
void finish(const PoseOptOptions& options, const std::vector<PoseObservation>& observations,
            const std::vector<double>& chi2, const BodyState& start, const BodyState& end,
            PoseOptResult* result) {
  double err2_px = 0.0;
  for (size_t k = 0; k < observations.size(); ++k) {
    if (!result->inliers[k]) continue;
    ++result->num_inliers;
    result->chi2_inliers += chi2[k];
    result->chi2_max = std::fmax(result->chi2_max, chi2[k]);
    err2_px += chi2[k] * observations[k].sigma_px * observations[k].sigma_px;
  }
  if (result->num_inliers > 0) result->rms_px = std::sqrt(err2_px / result->num_inliers);
  result->state = end.to_nav_state(result->state);

  if (!end.all_finite() || !std::isfinite(result->rms_px)) {
    result->status = PoseOptStatus::kNonFinite;
    result->reason = "non-finite estimate";
    return;
  }
  const double moved_m = (end.p_w_b - start.p_w_b).norm();
  const double turned_rad = so3::log(start.R_w_b.transpose() * end.R_w_b).norm();
  if (moved_m > options.max_translation_m || turned_rad > options.max_rotation_rad) {
    result->status = PoseOptStatus::kDiverged;
    result->reason = "moved " + std::to_string(moved_m) + " m / " + std::to_string(turned_rad) +
                     " rad from the initial guess";
  } else if (result->num_inliers < options.min_inliers) {
    result->status = PoseOptStatus::kTooFewInliers;
    result->reason = std::to_string(result->num_inliers) + " inliers < N_min " +
                     std::to_string(options.min_inliers);
  } else if (result->rms_px > options.max_rms_px) {
    result->status = PoseOptStatus::kRmsTooHigh;
    result->reason = "inlier RMS " + std::to_string(result->rms_px) + " px > " +
                     std::to_string(options.max_rms_px) + " px";
  } else {
    result->status = PoseOptStatus::kOk;
    result->reason.clear();
  }
}

PoseOptResult non_finite_input(const NavState& initial, size_t num_observations) {
  PoseOptResult result;
  result.state = initial;
  result.inliers.assign(num_observations, false);
  result.status = PoseOptStatus::kNonFinite;
  result.reason = "non-finite initial state";
  return result;
}

}  // namespace

const char* to_string(PoseOptStatus status) {
  switch (status) {
    case PoseOptStatus::kOk:
      return "ok";
    case PoseOptStatus::kNonFinite:
      return "non-finite";
    case PoseOptStatus::kTooFewInliers:
      return "too few inliers";
    case PoseOptStatus::kDiverged:
      return "diverged";
    case PoseOptStatus::kRmsTooHigh:
      return "reprojection error too high";
  }
  return "unknown";
}

PoseOptimizer::PoseOptimizer(const StereoCalib& calib, const PoseOptOptions& options,
                             const Eigen::Vector3d& g_w)
    : options_(options), visual_(calib, options.min_depth_m), g_w_(g_w) {
  if (options.rounds < 1 || options.iterations_per_round < 1 || !(options.chi2_threshold > 0.0)) {
    throw std::invalid_argument(
        "PoseOptOptions: rounds, iterations_per_round and chi2_threshold must be positive");
  }
}

PoseOptResult PoseOptimizer::optimise_pose(const NavState& initial,
                                           const std::vector<PoseObservation>& observations) const {
  const BodyState start = BodyState::from(initial);
  if (!start.all_finite()) return non_finite_input(initial, observations.size());
  PoseOptResult result;
  result.state = initial;
  JointState x{start, start};
  std::vector<double> chi2;
  NormalEquations<6> system;
  result.iterations = robust_rounds<6>({visual_, observations, nullptr}, options_, &x,
                                       &result.inliers, &chi2, &system);
  result.pose_covariance = covariance_or_zero<6>(system.H);
  finish(options_, observations, chi2, start, x.current, &result);
  return result;
}

PoseOptResult PoseOptimizer::optimise_inertial(const NavState& initial,
                                               const std::vector<PoseObservation>& observations,
                                               const ImuPreintegration& pim,
                                               const PreviousState& previous) const {
  if (pim.t1_ns() != initial.t_ns) {
    throw std::invalid_argument(
        "optimise_inertial: the preintegration does not end at the "
        "current state's time");
  }
  const InertialTerms inertial(pim, previous, g_w_);
  const BodyState start = BodyState::from(initial);
  if (!start.all_finite() || !inertial.previous().all_finite()) {
    return non_finite_input(initial, observations.size());
  }
  PoseOptResult result;
  result.state = initial;
  JointState x{start, inertial.previous()};
  std::vector<double> chi2;
  const Terms terms{visual_, observations, &inertial};
  if (previous.fixed) {
    NormalEquations<15> system;
    result.iterations = robust_rounds<15>(terms, options_, &x, &result.inliers, &chi2, &system);
    result.information = 0.5 * (system.H + system.H.transpose());
  } else {
    NormalEquations<30> system;
    result.iterations = robust_rounds<30>(terms, options_, &x, &result.inliers, &chi2, &system);
    result.information = marginalise_previous(system.H);
  }
  result.pose_covariance = covariance_or_zero<15>(result.information).topLeftCorner<6, 6>();
  result.chi2_imu = 2.0 * inertial.linearise(x.current, x.previous);
  finish(options_, observations, chi2, start, x.current, &result);
  return result;
}

}  // namespace hs
