#include "mapper/local_ba_problem.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "common/core/monotonic_clock.h"
#include "mapper/bias_walk_cost.h"
#include "mapper/gravity_prior_cost.h"
#include "mapper/imu_cost.h"

namespace hs {
namespace {

[[noreturn]] void fail(const std::string& what) {
  throw std::invalid_argument("LocalBundleAdjuster: " + what);
}

bool finite(const NavState& s) {
  return s.p_w_b.allFinite() && s.q_w_b.coeffs().allFinite() && s.q_w_b.norm() > 0.5 &&
         s.v_w.allFinite() && s.gyro_bias.allFinite() && s.accel_bias.allFinite();
}

// Index of every id; throws on duplicates.
template <class T>
std::unordered_map<int64_t, size_t> index_ids(const std::vector<T>& items, const char* kind) {
  std::unordered_map<int64_t, size_t> index;
  for (size_t k = 0; k < items.size(); ++k) {
    if (!index.emplace(items[k].id, k).second)
      fail(std::string("duplicate ") + kind + " id " + std::to_string(items[k].id));
  }
  return index;
}

// `who()` names the referrer; messages are built only on failure (a window has thousands of
// observations).
template <class Who>
size_t lookup(const std::unordered_map<int64_t, size_t>& index, int64_t id, const Who& who) {
  const auto it = index.find(id);
  if (it == index.end()) fail(who() + " refers to unknown id " + std::to_string(id));
  return it->second;
}

ceres::Problem::Options borrowing_problem_options() {
  ceres::Problem::Options o;
  o.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  o.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  o.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  o.enable_fast_removal = true;
  return o;
}

}  // namespace

LocalBaIndex resolve_local_ba_input(const LocalBaInput& in) {
  if (!(in.gravity.g_w.allFinite() && in.gravity.g_w.norm() > 0.0 &&
        std::isfinite(in.gravity.prior_sigma_rad)))
    fail("gravity is zero or not finite");
  const auto kf_index = index_ids(in.keyframes, "keyframe");
  const auto pt_index = index_ids(in.points, "point");
  for (const BaKeyframe& kf : in.keyframes) {
    if (!finite(kf.state)) fail("keyframe " + std::to_string(kf.id) + " has a non-finite state");
  }
  for (const BaPoint& pt : in.points) {
    if (!pt.p_w.allFinite()) fail("point " + std::to_string(pt.id) + " is not finite");
  }
  LocalBaIndex index;
  index.obs_keyframe.reserve(in.observations.size());
  index.obs_point.reserve(in.observations.size());
  for (size_t k = 0; k < in.observations.size(); ++k) {
    const BaObservation& obs = in.observations[k];
    const auto who = [k] { return "observation " + std::to_string(k); };
    index.obs_keyframe.push_back(lookup(kf_index, obs.keyframe_id, who));
    index.obs_point.push_back(lookup(pt_index, obs.point_id, who));
    if (obs.camera != 0 && obs.camera != 1) fail(who() + " has camera index not 0 or 1");
    if (!obs.uv.allFinite()) fail(who() + " has a non-finite pixel");
    if (!(std::isfinite(obs.sigma_px) && obs.sigma_px > 0.0)) fail(who() + " has sigma_px <= 0");
  }
  for (size_t k = 0; k < in.imu_factors.size(); ++k) {
    const BaImuFactor& f = in.imu_factors[k];
    const auto who = [k] { return "IMU factor " + std::to_string(k); };
    const size_t i = lookup(kf_index, f.keyframe_i, who);
    const size_t j = lookup(kf_index, f.keyframe_j, who);
    if (f.pim.t0_ns() != in.keyframes[i].state.t_ns ||
        f.pim.t1_ns() != in.keyframes[j].state.t_ns || j == i)
      fail(who() + " does not span its keyframes' times");
    index.imu_pairs.emplace_back(i, j);
  }
  return index;
}

LocalBaProblem::LocalBaProblem(const StereoCalib& calib, const LocalBaOptions& options,
                               const LocalBaInput& input, const LocalBaIndex& index)
    : options_(options),
      input_(input),
      index_(index),
      storage_(input.keyframes.size() * kKeyframeSize + 3 + 3 * input.points.size()),
      huber_(std::sqrt(options.chi2_threshold)),
      cameras_{RigCamera(calib.cam0), RigCamera(calib.cam1)},
      use_lm_(options.solver == LocalBaOptions::Solver::kSchurLm && !options.sparse &&
              !input.points.empty()),
      lm_([first_point = point(0)](const double* x) { return x >= first_point; }) {
  if (!use_lm_) problem_ = std::make_unique<ceres::Problem>(borrowing_problem_options());
  for (size_t k = 0; k < input.keyframes.size(); ++k) {
    state_to_blocks(input.keyframes[k].state, pose(k), speed_bias(k));
    add_block(pose(k), kPoseSize, &pose_manifold_);
  }
  for (size_t k = 0; k < input.points.size(); ++k)
    Eigen::Map<Eigen::Vector3d>{point(k)} = input.points[k].p_w;
  Eigen::Map<Eigen::Vector3d>{gravity_block()} = input.gravity.g_w;
  add_visual_terms();
  add_inertial_terms();
  fix_gauge();
  if (!use_lm_) configure_solver();
}

void LocalBaProblem::add_block(double* x, int size, ceres::Manifold* manifold) {
  if (use_lm_) {
    lm_.add_block(x, size, manifold);
  } else {
    problem_->AddParameterBlock(x, size, manifold);
  }
}

void LocalBaProblem::set_constant(double* x) {
  if (use_lm_) {
    lm_.set_constant(x);
  } else {
    problem_->SetParameterBlockConstant(x);
  }
}

bool LocalBaProblem::has_block(double* x) const {
  return use_lm_ ? lm_.has_block(x) : problem_->HasParameterBlock(x);
}

int LocalBaProblem::add_term(ceres::CostFunction* cost, ceres::LossFunction* loss,
                             std::initializer_list<double*> blocks) {
  if (use_lm_) return lm_.add_term(cost, loss, blocks);
  ceres_terms_.push_back(problem_->AddResidualBlock(cost, loss, std::vector<double*>(blocks)));
  return static_cast<int>(ceres_terms_.size()) - 1;
}

void LocalBaProblem::remove_term(int id) {
  if (use_lm_) {
    lm_.remove_term(id);
  } else {
    problem_->RemoveResidualBlock(ceres_terms_[static_cast<size_t>(id)]);
  }
}

bool LocalBaProblem::has_terms() const {
  return use_lm_ ? lm_.num_terms() > 0 : problem_->NumResidualBlocks() > 0;
}

void LocalBaProblem::add_visual_terms() {
  const size_t n = input_.observations.size();
  std::vector<size_t> by_point(n);
  std::iota(by_point.begin(), by_point.end(), size_t{0});
  std::stable_sort(by_point.begin(), by_point.end(),
                   [&](size_t a, size_t b) { return index_.obs_point[a] < index_.obs_point[b]; });
  reprojection_.resize(n);
  for (const size_t k : by_point) {
    const BaObservation& obs = input_.observations[k];
    reprojection_[k] = &reprojection_costs_.emplace_back(cameras_[obs.camera], obs.uv, obs.sigma_px,
                                                         options_.min_depth_m);
  }
  // Added in the input's order: Ceres keeps it within each point's rows, and the rounding of the
  // solve with it.
  reprojection_term_.assign(n, -1);
  for (size_t k = 0; k < n; ++k) {
    if (!std::isfinite(chi2(k))) continue;
    reprojection_term_[k] = add_term(reprojection_[k], &huber_,
                                     {pose(index_.obs_keyframe[k]), point(index_.obs_point[k])});
  }
  for (size_t k = 0; k < input_.points.size(); ++k) {
    if (input_.points[k].fixed && has_block(point(k))) set_constant(point(k));
  }
}

void LocalBaProblem::add_inertial_terms() {
  if (input_.imu_factors.empty()) return;
  const BaGravity& gravity = input_.gravity;
  if (gravity.prior_sigma_rad > 0.0) {
    add_block(gravity_block(), 3, &gravity_manifold_);
    inertial_.push_back(std::make_unique<GravityPriorCost>(gravity.g_w, gravity.prior_sigma_rad));
    add_term(inertial_.back().get(), nullptr, {gravity_block()});
  } else {
    add_block(gravity_block(), 3, nullptr);
    set_constant(gravity_block());
  }
  for (size_t k = 0; k < input_.imu_factors.size(); ++k) {
    const auto [i, j] = index_.imu_pairs[k];
    const ImuPreintegration& pim = input_.imu_factors[k].pim;
    inertial_.push_back(std::make_unique<ImuCost>(pim));
    add_term(inertial_.back().get(), nullptr,
             {pose(i), speed_bias(i), pose(j), speed_bias(j), gravity_block()});
    inertial_.push_back(std::make_unique<BiasWalkCost>(pim));
    add_term(inertial_.back().get(), nullptr, {speed_bias(i), speed_bias(j)});
  }
}

void LocalBaProblem::fix_gauge() {
  const std::vector<BaKeyframe>& kfs = input_.keyframes;
  bool any_fixed = false;
  for (size_t k = 0; k < kfs.size(); ++k) {
    if (!kfs[k].fixed && !kfs[k].pose_fixed) continue;
    any_fixed = true;
    set_constant(pose(k));
    if (kfs[k].fixed && has_block(speed_bias(k))) set_constant(speed_bias(k));
  }
  if (any_fixed || kfs.empty()) return;
  const auto oldest = std::min_element(
      kfs.begin(), kfs.end(),
      [](const BaKeyframe& a, const BaKeyframe& b) { return a.state.t_ns < b.state.t_ns; });
  set_constant(pose(static_cast<size_t>(oldest - kfs.begin())));
}

void LocalBaProblem::configure_solver() {
  solver_options_.max_num_iterations = options_.iterations_per_round;
  solver_options_.num_threads = options_.num_threads;
  solver_options_.logging_type = ceres::SILENT;
  // Points are eliminated first; keyframe blocks and gravity form the reduced system. Ceres
  // switches to a non-Schur solver itself if no point remains free.
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  std::vector<double*> blocks;
  problem_->GetParameterBlocks(&blocks);
  bool has_points = false;
  for (double* block : blocks) {
    const bool is_point = problem_->ParameterBlockSize(block) == 3 && block != gravity_block();
    has_points = has_points || is_point;
    ordering->AddElementToGroup(block, is_point ? 0 : 1);
  }
  const bool sparse_available =
      ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE);
  if (has_points) {
    solver_options_.linear_solver_type = ceres::DENSE_SCHUR;
    if (options_.sparse && sparse_available) {
      solver_options_.linear_solver_type = ceres::SPARSE_SCHUR;
      solver_options_.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
    }
    solver_options_.linear_solver_ordering = ordering;
  } else if (sparse_available) {
    // An inertial-only chain of many keyframes: banded, dense would be cubic in its length.
    solver_options_.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    solver_options_.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  } else {
    solver_options_.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  }
}

namespace {

// Ceres' own time limit is wall-clock; this one counts the solving thread's CPU time.
class CpuDeadline : public ceres::IterationCallback {
 public:
  explicit CpuDeadline(double deadline_s) : deadline_s_(deadline_s) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    return thread_cpu_s() < deadline_s_ ? ceres::SOLVER_CONTINUE
                                        : ceres::SOLVER_TERMINATE_SUCCESSFULLY;
  }

 private:
  double deadline_s_;
};

}  // namespace

SchurLmSummary LocalBaProblem::solve(double cpu_deadline_s, double function_tolerance) {
  if (use_lm_) {
    SchurLmOptions lm;
    lm.max_iterations = options_.iterations_per_round;
    lm.function_tolerance = function_tolerance;
    lm.keep_going = [cpu_deadline_s] { return thread_cpu_s() < cpu_deadline_s; };
    return lm_.solve(lm);
  }
  CpuDeadline deadline(cpu_deadline_s);
  ceres::Solver::Options options = solver_options_;
  options.function_tolerance = function_tolerance;
  options.callbacks.push_back(&deadline);
  ceres::Solver::Summary summary;
  ceres::Solve(options, problem_.get(), &summary);
  SchurLmSummary out;
  out.usable = summary.IsSolutionUsable();
  out.initial_cost = summary.initial_cost;
  out.final_cost = summary.final_cost;
  out.successful_steps = summary.num_successful_steps;
  out.unsuccessful_steps = summary.num_unsuccessful_steps;
  return out;
}

double LocalBaProblem::chi2(size_t k) const {
  const double* parameters[2] = {pose(index_.obs_keyframe[k]), point(index_.obs_point[k])};
  Eigen::Vector2d r;
  if (!reprojection_[k]->Evaluate(parameters, r.data(), nullptr)) {
    return std::numeric_limits<double>::infinity();
  }
  return r.squaredNorm();
}

void LocalBaProblem::drop_outliers(double chi2_threshold) {
  for (size_t k = 0; k < reprojection_term_.size(); ++k) {
    if (reprojection_term_[k] >= 0 && !(chi2(k) <= chi2_threshold)) {
      remove_term(reprojection_term_[k]);
      reprojection_term_[k] = -1;
    }
  }
}

void LocalBaProblem::estimate(std::vector<BaKeyframe>* keyframes, std::vector<BaPoint>* points,
                              Eigen::Vector3d* g_w) const {
  *g_w = Eigen::Map<const Eigen::Vector3d>(gravity_block());
  *keyframes = input_.keyframes;
  for (size_t k = 0; k < keyframes->size(); ++k) {
    blocks_to_state(pose(k), speed_bias(k), &(*keyframes)[k].state);
  }
  *points = input_.points;
  for (size_t k = 0; k < points->size(); ++k) {
    (*points)[k].p_w = Eigen::Map<const Eigen::Vector3d>(point(k));
  }
}

}  // namespace hs
