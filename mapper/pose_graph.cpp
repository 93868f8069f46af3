#include "mapper/pose_graph.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hs {
namespace {

template <typename T>
using Mat3 = Eigen::Matrix<T, 3, 3>;
template <typename T>
using Vec3 = Eigen::Matrix<T, 3, 1>;

template <typename T>
Mat3<T> rot_z(const T& yaw) {
  using std::cos, std::sin;
  Mat3<T> R = Mat3<T>::Identity();
  R(0, 0) = cos(yaw);
  R(0, 1) = -sin(yaw);
  R(1, 0) = sin(yaw);
  R(1, 1) = cos(yaw);
  return R;
}

template <typename T>
Mat3<T> exp_so3(const T* phi) {
  Mat3<T> R;
  ceres::AngleAxisToRotationMatrix(phi, ceres::ColumnMajorAdapter3x3(R.data()));
  return R;
}

// Residual of one edge given both poses: [R_i^T (p_j - p_i) - t_ij; Log(R_ij^T R_i^T R_j)],
// whitened.
struct EdgeError {
  Eigen::Matrix3d R_ij;
  Eigen::Vector3d t_ij;
  double w_t, w_r;

  template <typename T>
  void operator()(const Mat3<T>& R_i, const Vec3<T>& p_i, const Mat3<T>& R_j, const Vec3<T>& p_j,
                  T* r) const {
    Eigen::Map<Vec3<T>> r_t(r);
    r_t = w_t * (R_i.transpose() * (p_j - p_i) - t_ij.cast<T>());
    const Mat3<T> E = R_ij.cast<T>().transpose() * R_i.transpose() * R_j;
    ceres::RotationMatrixToAngleAxis(ceres::ColumnMajorAdapter3x3(E.data()), r + 3);
    for (int k = 3; k < 6; ++k) r[k] *= w_r;
  }
};

// 4-DoF node: [x, y, z, yaw], rotation Rz(yaw) * R_rp with roll/pitch R_rp held.
struct Edge4Dof {
  EdgeError e;
  Eigen::Matrix3d R_rp_i, R_rp_j;
  template <typename T>
  bool operator()(const T* a, const T* b, T* r) const {
    e(Mat3<T>(rot_z(a[3]) * R_rp_i.cast<T>()), Vec3<T>(a[0], a[1], a[2]),
      Mat3<T>(rot_z(b[3]) * R_rp_j.cast<T>()), Vec3<T>(b[0], b[1], b[2]), r);
    return true;
  }
};

// 6-DoF node: [phi (3), p (3)], rotation Exp(phi) * R_0.
struct Edge6Dof {
  EdgeError e;
  Eigen::Matrix3d R0_i, R0_j;
  template <typename T>
  bool operator()(const T* a, const T* b, T* r) const {
    e(Mat3<T>(exp_so3(a) * R0_i.cast<T>()), Vec3<T>(a[3], a[4], a[5]),
      Mat3<T>(exp_so3(b) * R0_j.cast<T>()), Vec3<T>(b[3], b[4], b[5]), r);
    return true;
  }
};

double yaw_of(const Eigen::Matrix3d& R) {
  return std::atan2(R(1, 0), R(0, 0));
}

}  // namespace

PoseGraphResult optimise_pose_graph(const std::map<int64_t, Eigen::Isometry3d>& T_w_b,
                                    const std::vector<PoseGraphEdge>& edges, int64_t fixed,
                                    const PoseGraphOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  // Per node: the rotation held fixed (roll/pitch for 4-DoF, the initial one for 6-DoF) and
  // the parameter block.
  std::map<int64_t, Eigen::Matrix3d> R_held;
  std::map<int64_t, std::vector<double>> params;
  for (const auto& [id, T] : T_w_b) {
    const Eigen::Vector3d& p = T.translation();
    if (options.four_dof) {
      const double yaw = yaw_of(T.linear());
      R_held[id] = rot_z(yaw).transpose() * T.linear();
      params[id] = {p.x(), p.y(), p.z(), yaw};
    } else {
      R_held[id] = T.linear();
      params[id] = {0, 0, 0, p.x(), p.y(), p.z()};
    }
  }
  ceres::Problem problem;
  const int n = options.four_dof ? 4 : 6;
  for (auto& [id, x] : params) problem.AddParameterBlock(x.data(), n);
  for (const PoseGraphEdge& edge : edges) {
    if (!params.count(edge.from) || !params.count(edge.to))
      throw std::invalid_argument("pose graph: edge " + std::to_string(edge.from) + " -> " +
                                  std::to_string(edge.to) + " names an absent pose");
    const EdgeError e{edge.T_from_to.linear(), edge.T_from_to.translation(),
                      std::sqrt(edge.weight) / options.sigma_m,
                      std::sqrt(edge.weight) / options.sigma_rad};
    ceres::CostFunction* cost =
        options.four_dof
            ? static_cast<ceres::CostFunction*>(new ceres::AutoDiffCostFunction<Edge4Dof, 6, 4, 4>(
                  new Edge4Dof{e, R_held[edge.from], R_held[edge.to]}))
            : new ceres::AutoDiffCostFunction<Edge6Dof, 6, 6, 6>(
                  new Edge6Dof{e, R_held[edge.from], R_held[edge.to]});
    problem.AddResidualBlock(cost, nullptr, params[edge.from].data(), params[edge.to].data());
  }
  if (params.count(fixed)) problem.SetParameterBlockConstant(params[fixed].data());

  ceres::Solver::Options so;
  so.max_num_iterations = options.max_iterations;
  so.num_threads = 1;
  if (ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE)) {
    so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    so.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  } else {
    so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  }
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);

  PoseGraphResult out;
  for (const auto& [id, x] : params) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    if (options.four_dof) {
      T.linear() = rot_z(x[3]) * R_held[id];
      T.translation() = Eigen::Vector3d(x[0], x[1], x[2]);
    } else {
      T.linear() = exp_so3(x.data()) * R_held[id];
      T.translation() = Eigen::Vector3d(x[3], x[4], x[5]);
    }
    out.T_w_b[id] = T;
  }
  out.iterations = static_cast<int>(summary.iterations.size());
  out.initial_cost = summary.initial_cost;
  out.final_cost = summary.final_cost;
  out.time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace hs
