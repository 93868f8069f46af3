#include "common/imu/vi_alignment.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "common/imu/so3.h"

namespace hs {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

// Added to every covariance so that the weights stay finite when all noise terms are set to 0.
constexpr double kCovarianceFloor = 1e-15;
// Gauss-Newton stops once an update is below this (rad/s for the bias, rad for the tilt).
constexpr double kConvergedStep = 1e-12;

std::string validate(const std::vector<TimedPose>& poses,
                     const std::vector<ImuPreintegration>& pims) {
  std::ostringstream why;
  if (poses.size() < 3) {
    why << "need at least 3 poses, got " << poses.size();
  } else if (pims.size() + 1 != poses.size()) {
    why << "need one preintegration per consecutive pose pair: " << poses.size() << " poses, "
        << pims.size() << " preintegrations";
  }
  for (size_t k = 0; why.tellp() == 0 && k < poses.size(); ++k) {
    const Eigen::Matrix3d R = poses[k].T_w_b.linear();
    if (!poses[k].T_w_b.matrix().allFinite()) {
      why << "pose " << k << " is not finite";
    } else if (!(R.transpose() * R).isIdentity(1e-6) || R.determinant() < 0.0) {
      why << "pose " << k << " rotation is not a rotation matrix";
    } else if (k > 0 && poses[k].t_ns <= poses[k - 1].t_ns) {
      why << "pose " << k << " time " << poses[k].t_ns << " ns is not after the previous one";
    }
  }
  for (size_t k = 0; why.tellp() == 0 && k < pims.size(); ++k) {
    const ImuPreintegration& pim = pims[k];
    const ImuDelta& d = pim.delta();
    if (pim.t1_ns() <= pim.t0_ns()) {
      why << "preintegration " << k << " is empty (no IMU data)";
    } else if (pim.t0_ns() != poses[k].t_ns || pim.t1_ns() != poses[k + 1].t_ns) {
      why << "preintegration " << k << " covers [" << pim.t0_ns() << ", " << pim.t1_ns()
          << "] ns but its poses are at " << poses[k].t_ns << " and " << poses[k + 1].t_ns;
    } else if (pim.status().has_gap()) {
      why << "preintegration " << k << " has an IMU gap of "
          << ns_to_s(pim.status().largest_gap_ns) * 1e3 << " ms";
    } else if (!d.R.allFinite() || !d.v.allFinite() || !d.p.allFinite() ||
               !pim.covariance().allFinite()) {
      why << "preintegration " << k << " is not finite";
    }
  }
  return why.str();
}

void reintegrate_all(std::vector<ImuPreintegration>& pims, const ImuBias& bias) {
  for (ImuPreintegration& pim : pims) pim.reintegrate(bias);
}

// 1 / sqrt(smallest eigenvalue): the largest marginal standard deviation of a Gaussian with this
// information matrix; infinite when it is singular.
double largest_sigma(const Eigen::MatrixXd& information) {
  const double lmin = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(information).eigenvalues()(0);
  return lmin > 0.0 ? 1.0 / std::sqrt(lmin) : std::numeric_limits<double>::infinity();
}

// Whitens the rows of a residual block with covariance `cov` = L L^T: multiplies them by L^-1.
template <class Rows, class Rhs>
void whiten(const Eigen::MatrixXd& cov, Rows&& rows, Rhs&& rhs) {
  const Eigen::LLT<Eigen::MatrixXd> llt(cov);
  llt.matrixL().solveInPlace(rows);
  llt.matrixL().solveInPlace(rhs);
}

// J^T J. Each residual block touches a few columns only: a sparse product skips the zeros
// that dominate the dense one (3x faster overall at 40 poses).
Eigen::MatrixXd normal_matrix(const Eigen::MatrixXd& J) {
  const Eigen::SparseMatrix<double> Js = J.sparseView();
  return Eigen::MatrixXd(Js.transpose() * Js);
}

// Through the normal equations: the whitened systems solved here are full rank (every unknown
// has a prior or is tied to one through the IMU).
Eigen::VectorXd solve_least_squares(const Eigen::MatrixXd& J, const Eigen::VectorXd& r) {
  return normal_matrix(J).ldlt().solve(-(J.transpose() * r));
}

double per_dof(double cost, Eigen::Index rows, Eigen::Index cols) {
  return rows > cols ? cost / static_cast<double>(rows - cols) : 0.0;
}

// Schur complement of `information` keeping the block [first, first + size).
Eigen::MatrixXd keep_block(const Eigen::MatrixXd& information, int first, int size) {
  const int n = static_cast<int>(information.cols());
  std::vector<int> other;
  for (int i = 0; i < n; ++i) {
    if (i < first || i >= first + size) other.push_back(i);
  }
  Eigen::MatrixXd H_kk = information.block(first, first, size, size);
  if (other.empty()) return H_kk;
  const int m = static_cast<int>(other.size());
  Eigen::MatrixXd H_oo(m, m), H_ok(m, size);
  for (int a = 0; a < m; ++a) {
    H_ok.row(a) = information.block(other[a], first, 1, size);
    for (int b = 0; b < m; ++b) H_oo(a, b) = information(other[a], other[b]);
  }
  return H_kk - H_ok.transpose() * H_oo.ldlt().solve(H_ok);
}

struct RotationSolution {
  std::vector<Eigen::Matrix3d> R_w_b;  // refined attitudes
  Eigen::Vector3d gyro_bias;
  double gyro_bias_sigma = 0.0;
  double correction_rms = 0.0;
  double chi2_per_dof = 0.0;
};

// Attitudes and gyro bias by Gauss-Newton on the vision attitudes (one independent prior each)
// and the preintegrated rotations between them:
//   Log(R_vis_i^T R_i) and Log(dR_ij(bg)^T R_i^T R_j), with R_i <- R_i Exp(phi_i).
// Leaves `pims` re-integrated at the returned gyro bias.
RotationSolution solve_rotations(const std::vector<TimedPose>& poses,
                                 std::vector<ImuPreintegration>& pims, const ImuBias& start,
                                 const ViAlignmentOptions& options) {
  const int n = static_cast<int>(poses.size());
  const int cols = 3 * n + 3, bg_col = 3 * n;
  const double sigma = std::sqrt(
      options.vision_rotation_sigma_rad * options.vision_rotation_sigma_rad + kCovarianceFloor);
  RotationSolution out;
  for (const TimedPose& pose : poses) out.R_w_b.push_back(pose.T_w_b.linear());
  ImuBias bias = start;
  reintegrate_all(pims, bias);
  // The deltas follow the bias to first order from their linearisation point (re-integrating at
  // each step made the tracker's mono scale check 8.9 ms instead of 7.6 on room_mav). Converged
  // that way, they are re-integrated and the iterations go on until a step leaves the
  // linearisation point where it was: the result is the exact one, whatever the start.
  // (Validated input has at least 3 poses, so pims is not empty.)
  const auto off_linearisation = [&] { return (bias.gyro - pims.front().bias().gyro).norm(); };
  double last_step = std::numeric_limits<double>::infinity();
  for (int it = 0;; ++it) {
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(3 * n + 3 * (n - 1), cols);
    Eigen::VectorXd r(J.rows());
    double correction_sq = 0.0;
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector3d r0 =
          so3::log(Eigen::Matrix3d(poses[i].T_w_b.linear().transpose() * out.R_w_b[i]));
      J.block<3, 3>(3 * i, 3 * i) = so3::right_jacobian_inverse(r0) / sigma;
      r.segment<3>(3 * i) = r0 / sigma;
      correction_sq += r0.squaredNorm();
    }
    for (int k = 0; k + 1 < n; ++k) {
      const ImuPreintegration& pim = pims[k];
      const Eigen::Matrix3d R_bi_bj = out.R_w_b[k].transpose() * out.R_w_b[k + 1];
      const Eigen::Matrix3d dR = pim.corrected(bias).R;
      const Eigen::Vector3d r0 = so3::log(Eigen::Matrix3d(dR.transpose() * R_bi_bj));
      const Eigen::Matrix3d Jinv = so3::right_jacobian_inverse(r0);
      const int row = 3 * n + 3 * k;
      auto rows = J.middleRows<3>(row);
      rows.block<3, 3>(0, 3 * k) = -Jinv * R_bi_bj.transpose();
      rows.block<3, 3>(0, 3 * k + 3) = Jinv;
      // Log(Exp(-A d) Exp(r0)) ~= r0 - Jr^-1(r0) Exp(r0)^T A d, with A = dR/dbg.
      rows.block<3, 3>(0, bg_col) = -Jinv * so3::exp(r0).transpose() * pim.dR_dbg();
      r.segment<3>(row) = r0;
      const Eigen::MatrixXd cov =
          pim.covariance().topLeftCorner<3, 3>() + kCovarianceFloor * Eigen::Matrix3d::Identity();
      whiten(cov, rows, r.segment<3>(row));
    }
    const bool converged = last_step < kConvergedStep;
    if (converged && off_linearisation() > kConvergedStep) {
      reintegrate_all(pims, bias);
      last_step = std::numeric_limits<double>::infinity();
      continue;
    }
    if (it >= options.gyro_bias_iterations || converged) {
      if (off_linearisation() > 0.0) reintegrate_all(pims, bias);
      out.gyro_bias = bias.gyro;
      out.gyro_bias_sigma = largest_sigma(keep_block(normal_matrix(J), bg_col, 3));
      out.correction_rms = std::sqrt(correction_sq / n);
      out.chi2_per_dof = per_dof(r.squaredNorm(), J.rows(), J.cols());
      return out;
    }
    const Eigen::VectorXd step = solve_least_squares(J, r);
    for (int i = 0; i < n; ++i) out.R_w_b[i] = out.R_w_b[i] * so3::exp(step.segment<3>(3 * i));
    bias.gyro += step.tail<3>();
    last_step = step.norm();
  }
}

// Whitened linear system |J x + r|^2 with unknowns x = [p_0 .. p_{N-1}, v_0 .. v_{N-1}, y,
// ba (optional)], gravity g = g0 + M y and ba relative to the preintegrations' linearisation
// point. Rows: the vision positions (one independent prior each), then for each pair, in the
// body frame of its first pose,
//   R_i^T (v_j - v_i - g dt) - (dv + dv_dba ba)
//   R_i^T (p_j - p_i - v_i dt - g dt^2 / 2) - (dp + dp_dba ba).
struct TranslationalSystem {
  Eigen::MatrixXd J;
  Eigen::VectorXd r;
  int num_states = 0;   // columns of the positions and velocities
  int num_gravity = 0;  // columns of y
  int drift_col = -1;   // the gyro bias correction's 3 columns when the vision may drift
  int scale_col = -1;   // the scale's column (last) when it is free
};

// Vision attitudes that drift slowly, as a mono visual odometry's do (a pitch drift of 0.75 deg/s
// on the real V1_01 flight): the gyro bias fitted to them in step (1) takes the drift, and
// the attitudes carry it into gravity's direction and from there into the scale. A correction
// `delta` to that bias moves attitude i (from the first, held) by Exp(A_i delta) along the
// preintegrated chain; the translational equations weigh it against the prior.
struct GyroDrift {
  std::vector<Eigen::Matrix3d> A;
  Eigen::Vector3d applied = Eigen::Vector3d::Zero();  // corrections so far (rad/s)
  double sigma = 0.0;                                 // prior on the total (rad/s)
};

// The preintegrated deltas at the gyro bias corrected by `drift` (first order: the corrections
// are small, and re-integrating at each step cost the tracker 10 ms per alignment).
ImuDelta drift_corrected(const ImuPreintegration& pim, const GyroDrift* drift) {
  return drift ? pim.corrected(drift->applied, Eigen::Vector3d::Zero()) : pim.delta();
}

// A_0 = 0, A_{i+1} = dR_i^T A_i + dR_i/dbg: the chain's Jacobian in each pose's body frame.
std::vector<Eigen::Matrix3d> chain_jacobians(const std::vector<ImuPreintegration>& pims,
                                             const GyroDrift& drift) {
  std::vector<Eigen::Matrix3d> A{Eigen::Matrix3d::Zero()};
  for (const ImuPreintegration& pim : pims)
    A.push_back(drift_corrected(pim, &drift).R.transpose() * A.back() + pim.dR_dbg());
  return A;
}

// The vision positions as a prior on the body positions: p_i = s * a_i + b_i, with s = 1 (a the
// metric positions, b zero) or a free scale (a the up-to-scale camera positions, b the metric
// camera-to-body lever arm in the world).
struct PositionPrior {
  std::vector<Eigen::Vector3d> a, b;
  bool free_scale = false;
};

PositionPrior metric_prior(const std::vector<TimedPose>& poses) {
  PositionPrior prior;
  for (const TimedPose& pose : poses) {
    prior.a.push_back(pose.T_w_b.translation());
    prior.b.push_back(Eigen::Vector3d::Zero());
  }
  return prior;
}

TranslationalSystem build_translational(const PositionPrior& prior,
                                        const std::vector<Eigen::Matrix3d>& R_w_b,
                                        const std::vector<ImuPreintegration>& pims,
                                        const Eigen::Vector3d& g0, const Eigen::MatrixXd& M,
                                        bool with_accel_bias, const ViAlignmentOptions& options,
                                        const GyroDrift* drift = nullptr) {
  const int n = static_cast<int>(prior.a.size());
  TranslationalSystem s;
  s.num_states = 6 * n;
  s.num_gravity = static_cast<int>(M.cols());
  const int g_col = s.num_states, ba_col = s.num_states + s.num_gravity;
  int cols = ba_col + (with_accel_bias ? 3 : 0);
  if (drift) {
    s.drift_col = cols;
    cols += 3;
  }
  if (prior.free_scale) s.scale_col = cols;
  const bool bias_prior = with_accel_bias && options.accel_bias_prior_sigma > 0.0;
  const int prior_rows = (bias_prior ? 3 : 0) + (drift ? 3 : 0);
  s.J.setZero(3 * n + 6 * (n - 1) + prior_rows, cols + (prior.free_scale ? 1 : 0));
  s.r.setZero(s.J.rows());
  const double sigma_p = std::sqrt(
      options.vision_position_sigma_m * options.vision_position_sigma_m + kCovarianceFloor);
  const double var_R = options.vision_rotation_sigma_rad * options.vision_rotation_sigma_rad;
  for (int i = 0; i < n; ++i) {
    s.J.block<3, 3>(3 * i, 3 * i).diagonal().setConstant(1.0 / sigma_p);
    if (prior.free_scale) {
      s.J.block<3, 1>(3 * i, s.scale_col) = -prior.a[i] / sigma_p;
      s.r.segment<3>(3 * i) = -prior.b[i] / sigma_p;
    } else {
      s.r.segment<3>(3 * i) = -(prior.a[i] + prior.b[i]) / sigma_p;
    }
  }
  for (int k = 0; k + 1 < n; ++k) {
    const ImuPreintegration& pim = pims[k];
    const ImuDelta d = drift_corrected(pim, drift);
    const double dt = pim.dt_s();
    const Eigen::Matrix3d Rt = R_w_b[k].transpose();
    const int row = 3 * n + 6 * k;
    const int pi = 3 * k, pj = pi + 3, vi = 3 * n + 3 * k, vj = vi + 3;
    auto rows = s.J.middleRows<6>(row);
    rows.block<3, 3>(0, vj) = Rt;
    rows.block<3, 3>(0, vi) = -Rt;
    rows.block(0, g_col, 3, s.num_gravity) = -dt * Rt * M;
    rows.block<3, 3>(3, pj) = Rt;
    rows.block<3, 3>(3, pi) = -Rt;
    rows.block<3, 3>(3, vi) = -dt * Rt;
    rows.block(3, g_col, 3, s.num_gravity) = -0.5 * dt * dt * Rt * M;
    if (with_accel_bias) {
      rows.block<3, 3>(0, ba_col) = -pim.dv_dba();
      rows.block<3, 3>(3, ba_col) = -pim.dp_dba();
    }
    if (drift) {
      // R_k(delta)^T x ~= R_k^T x + hat(R_k^T x) A_k delta, with R_k^T x ~= dv (dp) at the
      // solution; the deltas move with the bias too.
      rows.block<3, 3>(0, s.drift_col) = so3::hat(d.v) * drift->A[k] - pim.dv_dbg();
      rows.block<3, 3>(3, s.drift_col) = so3::hat(d.p) * drift->A[k] - pim.dp_dbg();
    }
    s.r.segment<3>(row) = -dt * Rt * g0 - d.v;
    s.r.segment<3>(row + 3) = -0.5 * dt * dt * Rt * g0 - d.p;
    // IMU noise, plus the attitude error of R_i acting on the (dv- and dp-sized) world terms.
    Matrix6d cov = pim.covariance().bottomRightCorner<6, 6>();
    cov.diagonal().head<3>().array() += var_R * d.v.squaredNorm() + kCovarianceFloor;
    cov.diagonal().tail<3>().array() += var_R * d.p.squaredNorm() + kCovarianceFloor;
    whiten(cov, rows, s.r.segment<6>(row));
  }
  // The bias about its linearisation value (residual zero there).
  int row = 3 * n + 6 * (n - 1);
  if (bias_prior) {
    s.J.block<3, 3>(row, ba_col).diagonal().setConstant(1.0 / options.accel_bias_prior_sigma);
    row += 3;
  }
  if (drift) {
    s.J.block<3, 3>(row, s.drift_col).diagonal().setConstant(1.0 / drift->sigma);
    s.r.segment<3>(row) = drift->applied / drift->sigma;
  }
  return s;
}

// Two unit vectors spanning the plane orthogonal to the unit vector `n`.
Eigen::Matrix<double, 3, 2> tangent_basis(const Eigen::Vector3d& n) {
  const Eigen::Vector3d a =
      std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  Eigen::Matrix<double, 3, 2> B;
  B.col(0) = n.cross(a).normalized();
  B.col(1) = n.cross(B.col(0));
  return B;
}

struct SphereSolution {
  Eigen::Vector3d dir;  // unit gravity direction
  Eigen::VectorXd x;    // [positions, velocities, tilt update (~0), accel bias (optional)]
  TranslationalSystem system;
};

// Gauss-Newton on the gravity direction; positions, velocities and accel bias enter linearly
// and are re-solved with it. Returns the solution at the final direction (tilt update ~0).
// With `drift`, the gyro bias correction is a Gauss-Newton unknown too: each step moves the
// attitudes along the chain.
SphereSolution refine_on_sphere(const PositionPrior& prior, std::vector<Eigen::Matrix3d>& R_w_b,
                                const std::vector<ImuPreintegration>& pims,
                                const Eigen::Vector3d& dir0, bool with_accel_bias,
                                const ViAlignmentOptions& options, GyroDrift* drift = nullptr) {
  const double G = options.gravity_magnitude;
  SphereSolution out;
  out.dir = dir0.normalized();
  for (int it = 0;; ++it) {
    const Eigen::Matrix<double, 3, 2> B = tangent_basis(out.dir);
    // g(theta) = G Exp(B theta) dir ~= G dir - G hat(dir) B theta.
    const Eigen::MatrixXd M = -G * so3::hat(out.dir) * B;
    if (drift) drift->A = chain_jacobians(pims, *drift);
    out.system =
        build_translational(prior, R_w_b, pims, G * out.dir, M, with_accel_bias, options, drift);
    out.x = solve_least_squares(out.system.J, out.system.r);
    const Eigen::Vector2d theta = out.x.segment<2>(out.system.num_states);
    const Eigen::Vector3d d =
        drift ? Eigen::Vector3d(out.x.segment<3>(out.system.drift_col)) : Eigen::Vector3d::Zero();
    if (it == options.gravity_iterations ||
        (theta.norm() < kConvergedStep && d.norm() < kConvergedStep))
      return out;
    out.dir = (so3::exp(B * theta) * out.dir).normalized();
    if (drift) {
      for (size_t i = 0; i < R_w_b.size(); ++i) R_w_b[i] = R_w_b[i] * so3::exp(drift->A[i] * d);
      drift->applied += d;
    }
  }
}

std::string describe_failure(const char* what, const Eigen::Vector3d& value, const char* unit,
                             const char* limit, double bound) {
  std::ostringstream why;
  why << what << " " << value.transpose() << " " << unit << " " << limit << " " << bound;
  return why.str();
}

}  // namespace

namespace {

// `poses` give the attitudes, `prior` the positions.
ViAlignmentResult align(const std::vector<TimedPose>& poses, const PositionPrior& prior,
                        const std::vector<ImuPreintegration>& input_pims,
                        const ViAlignmentOptions& options) {
  ViAlignmentResult out;
  out.reason = validate(poses, input_pims);
  if (!out.reason.empty()) return out;
  const double G = options.gravity_magnitude;
  const int n = static_cast<int>(poses.size());
  std::vector<ImuPreintegration> pims = input_pims;
  const ImuBias start = pims.front().bias();
  out.accel_bias = start.accel;

  // (1) Attitudes and gyro bias.
  const RotationSolution rot = solve_rotations(poses, pims, start, options);
  out.gyro_bias = rot.gyro_bias;
  out.gyro_bias_sigma = rot.gyro_bias_sigma;
  out.rotation_correction_rms_rad = rot.correction_rms;
  out.rotation_chi2_per_dof = rot.chi2_per_dof;
  if (!rot.gyro_bias.allFinite() || rot.gyro_bias.norm() > options.max_gyro_bias_norm) {
    out.reason = describe_failure("gyro bias estimate", rot.gyro_bias, "rad/s", "exceeds",
                                  options.max_gyro_bias_norm);
    return out;
  }

  // (2) Positions, velocities and unconstrained gravity.
  const TranslationalSystem linear = build_translational(
      prior, rot.R_w_b, pims, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), false, options);
  const Eigen::VectorXd x_free = solve_least_squares(linear.J, linear.r);
  const Eigen::Vector3d g_free = x_free.segment<3>(linear.num_states);
  if (prior.free_scale) {
    // Scale comes from accelerations only: without enough of them it is not observed.
    const double scale = x_free(linear.scale_col);
    const double sigma = largest_sigma(keep_block(normal_matrix(linear.J), linear.scale_col, 1));
    if (!(scale > 0.0) || !(sigma <= options.max_scale_sigma * scale)) {
      std::ostringstream why;
      why << "not enough acceleration: scale " << scale << " +- " << sigma;
      out.reason = why.str();
      return out;
    }
  }
  out.gravity_norm_unconstrained = g_free.norm();
  if (!g_free.allFinite() || std::abs(g_free.norm() - G) > options.max_gravity_norm_error) {
    out.reason =
        describe_failure("unconstrained gravity", g_free, "m/s^2",
                         "has a magnitude off G by more than", options.max_gravity_norm_error);
    return out;
  }

  // (3) Gravity on the sphere, then with the accel bias if the window separates the two.
  std::vector<Eigen::Matrix3d> R_w_b = rot.R_w_b;
  SphereSolution sol = refine_on_sphere(prior, R_w_b, pims, g_free, false, options);
  const int tilt_col = sol.system.num_states;
  if (options.estimate_accel_bias) {
    // What the window alone says (without the bias prior).
    ViAlignmentOptions data_only = options;
    data_only.accel_bias_prior_sigma = 0.0;
    const TranslationalSystem probe =
        build_translational(prior, R_w_b, pims, G * sol.dir,
                            -G * so3::hat(sol.dir) * tangent_basis(sol.dir), true, data_only);
    // Tilt and bias information, the tilt scaled to m/s^2 (G * theta) to compare the two.
    Eigen::MatrixXd info = keep_block(normal_matrix(probe.J), tilt_col, 5);
    info.topRows<2>() /= G;
    info.leftCols<2>() /= G;
    const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(info).eigenvalues();
    out.gravity_accel_bias_conditioning = eig(4) > 0.0 ? std::max(eig(0), 0.0) / eig(4) : 0.0;
    out.accel_bias_sigma = largest_sigma(keep_block(info, 2, 3));
    out.weak_excitation = !(out.accel_bias_sigma <= options.max_accel_bias_sigma);
    if (!out.weak_excitation || options.accel_bias_prior_sigma > 0.0) {
      sol = refine_on_sphere(prior, R_w_b, pims, sol.dir, true, options);
      out.accel_bias_estimated = true;
      out.accel_bias = start.accel + sol.x.segment<3>(tilt_col + 2);
    }
  }
  if (options.vision_rotation_drift_sigma > 0.0) {
    // (4) The gyro bias again, from the translational equations under a prior of the drift.
    GyroDrift drift;
    drift.sigma = options.vision_rotation_drift_sigma;
    sol = refine_on_sphere(prior, R_w_b, pims, sol.dir, out.accel_bias_estimated, options, &drift);
    out.gyro_bias = rot.gyro_bias + drift.applied;
    if (out.accel_bias_estimated) out.accel_bias = start.accel + sol.x.segment<3>(tilt_col + 2);
  }
  if (!sol.x.allFinite()) {
    out.reason = "alignment produced non-finite estimates";
    return out;
  }
  const TranslationalSystem& s = sol.system;
  out.tilt_sigma_rad = largest_sigma(keep_block(normal_matrix(s.J), tilt_col, 2));
  out.translation_chi2_per_dof = per_dof((s.J * sol.x + s.r).squaredNorm(), s.J.rows(), s.J.cols());
  if (prior.free_scale) {
    out.scale = sol.x(s.scale_col);
    out.scale_sigma = largest_sigma(keep_block(normal_matrix(s.J), s.scale_col, 1));
  }
  double position_sq = 0.0;
  for (int i = 0; i < n; ++i) {
    position_sq += (sol.x.segment<3>(3 * i) - out.scale * prior.a[i] - prior.b[i]).squaredNorm();
    out.v_w.push_back(sol.x.segment<3>(3 * n + 3 * i));
  }
  out.position_correction_rms_m = std::sqrt(position_sq / n);
  out.g_w = G * sol.dir;
  // Minimal rotation (about a horizontal axis), so no yaw is introduced.
  out.R_wg_w = Eigen::Quaterniond::FromTwoVectors(sol.dir, default_gravity_w()).toRotationMatrix();
  out.ok = true;
  return out;
}

}  // namespace

ViAlignmentResult align_visual_inertial(const std::vector<TimedPose>& poses,
                                        const std::vector<ImuPreintegration>& pims,
                                        const ViAlignmentOptions& options) {
  return align(poses, metric_prior(poses), pims, options);
}

ViAlignmentResult align_visual_inertial_up_to_scale(const std::vector<TimedPose>& camera_poses,
                                                    const Eigen::Isometry3d& T_b_c,
                                                    const std::vector<ImuPreintegration>& pims,
                                                    const ViAlignmentOptions& options) {
  const Eigen::Isometry3d T_c_b = T_b_c.inverse();
  std::vector<TimedPose> body;
  PositionPrior prior;
  prior.free_scale = true;
  for (const TimedPose& c : camera_poses) {
    body.push_back({c.t_ns, c.T_w_b * T_c_b});
    prior.a.push_back(c.T_w_b.translation());
    prior.b.push_back(c.T_w_b.linear() * T_c_b.translation());
  }
  return align(body, prior, pims, options);
}

}  // namespace hs
