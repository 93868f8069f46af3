#include "common/eval/align.h"

#include <Eigen/SVD>
#include <limits>

#include "common/core/error.h"

namespace hs {

Sim3 umeyama(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst,
             bool with_scale) {
  if (src.size() != dst.size() || src.empty())
    throw InputError("umeyama: need two equally long, non-empty point sets");
  const double n = static_cast<double>(src.size());
  Eigen::Vector3d mean_src = Eigen::Vector3d::Zero(), mean_dst = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < src.size(); ++i) {
    mean_src += src[i];
    mean_dst += dst[i];
  }
  mean_src /= n;
  mean_dst /= n;
  double var_src = 0.0;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();  // Umeyama eq. 38: (1/n) sum dst' src'^T
  for (size_t i = 0; i < src.size(); ++i) {
    const Eigen::Vector3d a = src[i] - mean_src;
    var_src += a.squaredNorm();
    cov += (dst[i] - mean_dst) * a.transpose();
  }
  var_src /= n;
  cov /= n;

  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d d = svd.singularValues();
  const Eigen::Index rank = (d.array() > std::numeric_limits<double>::epsilon()).count();
  if (rank < 2)
    throw InputError("umeyama: degenerate point configuration (covariance rank " +
                     std::to_string(rank) + "), alignment is not possible");
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) S(2, 2) = -1.0;

  Sim3 out;
  out.R = svd.matrixU() * S * svd.matrixV().transpose();
  out.s = with_scale ? (d.asDiagonal() * S).trace() / var_src : 1.0;
  out.t = mean_dst - out.s * out.R * mean_src;
  return out;
}

Sim3 compute_alignment(const Trajectory& gt, const Trajectory& est, AlignMode mode) {
  if (gt.poses.size() != est.poses.size() || est.poses.empty())
    throw InputError("alignment needs two equally long, non-empty trajectories");
  Sim3 out;
  switch (mode) {
    case AlignMode::kNone:
      break;
    case AlignMode::kOrigin: {
      const Eigen::Isometry3d T = gt.poses[0].T_w_b * est.poses[0].T_w_b.inverse();
      out.R = T.linear();
      out.t = T.translation();
      break;
    }
    case AlignMode::kSe3:
    case AlignMode::kSim3:
    case AlignMode::kScale: {
      std::vector<Eigen::Vector3d> src, dst;
      for (size_t i = 0; i < est.poses.size(); ++i) {
        src.push_back(est.poses[i].T_w_b.translation());
        dst.push_back(gt.poses[i].T_w_b.translation());
      }
      out = umeyama(src, dst, mode != AlignMode::kSe3);
      if (mode == AlignMode::kScale) {
        out.R.setIdentity();
        out.t.setZero();
      }
      break;
    }
  }
  return out;
}

void apply_alignment(const Sim3& S, Trajectory& trajectory) {
  for (StampedPose& pose : trajectory.poses) {
    pose.T_w_b.translation() = S.R * (S.s * pose.T_w_b.translation()) + S.t;
    pose.T_w_b.linear() = S.R * pose.T_w_b.linear();
  }
}

}  // namespace hs
