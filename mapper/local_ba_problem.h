#pragma once
// The problem of one local bundle adjustment (mapper/local_ba.h): input validation, parameter
// blocks, cost terms and gauge, held by mapper/schur_lm.h or, for Ceres' own solver, by a
// ceres::Problem with the Schur ordering (points eliminated first).
#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <ceres/sphere_manifold.h>

#include <array>
#include <cstddef>
#include <deque>
#include <initializer_list>
#include <memory>
#include <utility>
#include <vector>

#include "mapper/local_ba.h"
#include "mapper/pose_manifold.h"
#include "mapper/reprojection_cost.h"
#include "mapper/schur_lm.h"

namespace hs {

// The input's cross references resolved to indices.
struct LocalBaIndex {
  std::vector<size_t> obs_keyframe, obs_point;       // per observation
  std::vector<std::pair<size_t, size_t>> imu_pairs;  // per IMU factor: keyframes i, j
};

// Validates the input (see LocalBundleAdjuster::optimise) and resolves its ids.
LocalBaIndex resolve_local_ba_input(const LocalBaInput& input);

class LocalBaProblem {
 public:
  // `input` and `index` must outlive the problem. Observations that cannot be projected at the
  // initial estimate are left out.
  LocalBaProblem(const StereoCalib& calib, const LocalBaOptions& options, const LocalBaInput& input,
                 const LocalBaIndex& index);

  bool has_terms() const;
  // At most options.iterations_per_round iterations, stopping at function_tolerance (the round's
  // own: see LocalBaOptions); none begins once the calling thread's CPU time (thread_cpu_s) has
  // passed cpu_deadline_s.
  SchurLmSummary solve(double cpu_deadline_s, double function_tolerance);
  // Whitened squared reprojection error of observation k at the current estimate; infinity
  // when it cannot be projected.
  double chi2(size_t k) const;
  // Removes the observations with chi2 above the threshold from the problem.
  void drop_outliers(double chi2_threshold);
  // The current estimate, in the input's order.
  void estimate(std::vector<BaKeyframe>* keyframes, std::vector<BaPoint>* points,
                Eigen::Vector3d* g_w) const;

 private:
  // The same problem for either solver.
  void add_block(double* x, int size, ceres::Manifold* manifold);
  void set_constant(double* x);
  bool has_block(double* x) const;
  int add_term(ceres::CostFunction* cost, ceres::LossFunction* loss,
               std::initializer_list<double*> blocks);
  void remove_term(int id);

  void add_visual_terms();
  void add_inertial_terms();
  void fix_gauge();
  void configure_solver();

  const LocalBaOptions& options_;
  const LocalBaInput& input_;
  const LocalBaIndex& index_;
  // Every parameter block in one buffer: keyframe k's pose and speed/bias, then gravity, then
  // the points. Ceres orders the blocks of a Schur group by address, so their addresses must
  // follow the input's order for a run to be repeatable (separate buffers' relative addresses
  // change with the heap, and with them the rounding of the solve).
  static constexpr size_t kKeyframeSize = kPoseSize + kSpeedBiasSize;
  double* pose(size_t k) { return storage_.data() + k * kKeyframeSize; }
  const double* pose(size_t k) const { return storage_.data() + k * kKeyframeSize; }
  double* speed_bias(size_t k) { return pose(k) + kPoseSize; }
  const double* speed_bias(size_t k) const { return pose(k) + kPoseSize; }
  double* gravity_block() { return pose(input_.keyframes.size()); }
  const double* gravity_block() const { return pose(input_.keyframes.size()); }
  double* point(size_t k) { return gravity_block() + 3 + 3 * k; }
  const double* point(size_t k) const { return gravity_block() + 3 + 3 * k; }

  std::vector<double> storage_;
  // The problem borrows the cost functions, loss and manifold, so that removed residual blocks
  // can still be evaluated for the final outlier flags.
  PoseManifold pose_manifold_;
  ceres::SphereManifold<3> gravity_manifold_;
  ceres::HuberLoss huber_;
  RigCamera cameras_[2];
  // Built point by point, the order in which Ceres' Schur ordering evaluates them: consecutive
  // costs are then neighbours in memory (a deque never moves them).
  std::deque<ReprojectionCost> reprojection_costs_;
  std::vector<ReprojectionCost*> reprojection_;  // per observation
  std::vector<int> reprojection_term_;           // per observation; -1 when not in the problem
  std::vector<std::unique_ptr<ceres::CostFunction>> inertial_;
  // Without points the problem is an inertial chain (the IMU refinement: up to 150 keyframes),
  // banded, which Ceres solves sparse; so is the full BA (`sparse`).
  bool use_lm_;
  SchurLm lm_;
  std::unique_ptr<ceres::Problem> problem_;          // Ceres' solver only
  std::vector<ceres::ResidualBlockId> ceres_terms_;  // by add_term's id
  ceres::Solver::Options solver_options_;
};

}  // namespace hs
