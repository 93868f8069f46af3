#include "common/eval/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>

#include "common/core/error.h"

namespace hs {
namespace {

double rotation_angle_rad(const Eigen::Matrix3d& R) {
  return Eigen::AngleAxisd(Eigen::Quaterniond(R).normalized()).angle();
}

// Error of one SE(3) error pose E under `relation` (everything but the APE translation part,
// which evo takes from positions directly).
double pose_error(const Eigen::Isometry3d& E, PoseRelation relation) {
  switch (relation) {
    case PoseRelation::kTransPart:
      return E.translation().norm();
    case PoseRelation::kRotPart:
      return (E.linear() - Eigen::Matrix3d::Identity()).norm();
    case PoseRelation::kFull:
      return (E.matrix() - Eigen::Matrix4d::Identity()).norm();
    case PoseRelation::kAngleRad:
      return rotation_angle_rad(E.linear());
    case PoseRelation::kAngleDeg:
      return rotation_angle_rad(E.linear()) * 180.0 / M_PI;
  }
  return 0.0;
}

void require_same_length(const Trajectory& gt, const Trajectory& est) {
  if (gt.poses.size() != est.poses.size())
    throw InputError("trajectories must be associated (same number of poses)");
}

std::vector<IndexPair> consecutive(const std::vector<size_t>& ids) {
  std::vector<IndexPair> pairs;
  for (size_t k = 1; k < ids.size(); ++k) pairs.emplace_back(ids[k - 1], ids[k]);
  return pairs;
}

std::vector<IndexPair> pairs_by_frames(size_t n, size_t delta, bool all_pairs) {
  if (all_pairs) {
    std::vector<IndexPair> pairs;
    for (size_t i = 0; i + delta < n; ++i) pairs.emplace_back(i, i + delta);
    return pairs;
  }
  std::vector<size_t> ids;
  for (size_t i = 0; i < n; i += delta) ids.push_back(i);
  return consecutive(ids);
}

std::vector<IndexPair> pairs_by_path(const Trajectory& est, double delta, double tol,
                                     bool all_pairs) {
  const std::vector<StampedPose>& poses = est.poses;
  std::vector<double> path(poses.size(), 0.0);  // travelled distance from pose 0
  for (size_t i = 1; i < poses.size(); ++i)
    path[i] =
        path[i - 1] + (poses[i].T_w_b.translation() - poses[i - 1].T_w_b.translation()).norm();
  if (all_pairs) {
    std::vector<IndexPair> pairs;
    // path is non-decreasing: the j > i nearest path[i] + delta (the first of equals, as
    // numpy.argmin) is the first of the run just below the target or the first at/above it.
    for (size_t i = 0; i + 1 < poses.size(); ++i) {
      const auto first = path.begin() + static_cast<std::ptrdiff_t>(i + 1);
      auto best = std::lower_bound(first, path.end(), path[i] + delta);
      if (best == path.end() || (best != first && std::abs(*(best - 1) - path[i] - delta) <=
                                                      std::abs(*best - path[i] - delta)))
        best = std::lower_bound(first, best, *(best - 1));
      if (std::abs(*best - path[i] - delta) <= tol)
        pairs.emplace_back(i, static_cast<size_t>(best - path.begin()));
    }
    return pairs;
  }
  std::vector<size_t> ids;
  double since_last = 0.0;
  for (size_t i = 1; i < poses.size(); ++i) {
    since_last += (poses[i].T_w_b.translation() - poses[i - 1].T_w_b.translation()).norm();
    if (since_last >= delta) {
      ids.push_back(i);
      since_last = 0.0;
    }
  }
  return consecutive(ids);
}

}  // namespace

PoseRelation parse_pose_relation(const std::string& name) {
  if (name == "trans_part" || name == "trans") return PoseRelation::kTransPart;
  if (name == "rot_part") return PoseRelation::kRotPart;
  if (name == "full") return PoseRelation::kFull;
  if (name == "angle_deg" || name == "rot_angle_deg") return PoseRelation::kAngleDeg;
  if (name == "angle_rad") return PoseRelation::kAngleRad;
  throw InputError("unknown pose relation '" + name +
                   "' (trans_part, rot_part, full, angle_deg, angle_rad)");
}

const char* relation_name(PoseRelation relation) {
  switch (relation) {
    case PoseRelation::kTransPart:
      return "trans_part";
    case PoseRelation::kRotPart:
      return "rot_part";
    case PoseRelation::kFull:
      return "full";
    case PoseRelation::kAngleDeg:
      return "angle_deg";
    case PoseRelation::kAngleRad:
      return "angle_rad";
  }
  return "";
}

const char* relation_title(PoseRelation relation) {
  switch (relation) {
    case PoseRelation::kTransPart:
      return "translation part";
    case PoseRelation::kRotPart:
      return "rotation part";
    case PoseRelation::kFull:
      return "full transformation";
    case PoseRelation::kAngleDeg:
    case PoseRelation::kAngleRad:
      return "rotation angle";
  }
  return "";
}

const char* relation_unit(PoseRelation relation) {
  switch (relation) {
    case PoseRelation::kTransPart:
      return "m";
    case PoseRelation::kAngleDeg:
      return "deg";
    case PoseRelation::kAngleRad:
      return "rad";
    case PoseRelation::kRotPart:
    case PoseRelation::kFull:
      break;
  }
  return "";
}

ErrorSeries compute_ape(const Trajectory& gt, const Trajectory& est, PoseRelation relation) {
  require_same_length(gt, est);
  ErrorSeries out;
  for (size_t i = 0; i < est.poses.size(); ++i) {
    const Eigen::Isometry3d& P = est.poses[i].T_w_b;
    const Eigen::Isometry3d& Q = gt.poses[i].T_w_b;
    out.t_ns.push_back(est.poses[i].t_ns);
    out.values.push_back(relation == PoseRelation::kTransPart
                             ? (P.translation() - Q.translation()).norm()
                             : pose_error(P.inverse() * Q, relation));
  }
  return out;
}

std::vector<IndexPair> rpe_pairs(const Trajectory& est, double delta, DeltaUnit unit,
                                 bool all_pairs, double rel_delta_tol) {
  std::vector<IndexPair> pairs;
  if (unit == DeltaUnit::kFrames) {
    if (!(delta >= 1.0) || delta != std::floor(delta))
      throw InputError("RPE delta in frames must be a positive integer");
    if (delta < static_cast<double>(est.poses.size()))  // larger deltas give no pairs anyway
      pairs = pairs_by_frames(est.poses.size(), static_cast<size_t>(delta), all_pairs);
  } else {
    if (!(delta > 0.0)) throw InputError("RPE delta in metres must be positive");
    pairs = pairs_by_path(est, delta, delta * rel_delta_tol, all_pairs);
  }
  if (pairs.empty()) {
    std::ostringstream msg;
    msg << "RPE delta " << delta << (unit == DeltaUnit::kFrames ? " (frames)" : " (m)")
        << " gives no pose pairs among " << est.poses.size() << " poses: try a smaller delta";
    throw InputError(msg.str());
  }
  return pairs;
}

ErrorSeries compute_rpe(const Trajectory& gt, const Trajectory& est,
                        const std::vector<IndexPair>& pairs, PoseRelation relation) {
  require_same_length(gt, est);
  ErrorSeries out;
  for (const auto& [i, j] : pairs) {
    if (i >= est.poses.size() || j >= est.poses.size())
      throw InputError("RPE pair index out of range");
    const Eigen::Isometry3d Q_ij = gt.poses[i].T_w_b.inverse() * gt.poses[j].T_w_b;
    const Eigen::Isometry3d P_ij = est.poses[i].T_w_b.inverse() * est.poses[j].T_w_b;
    out.t_ns.push_back(est.poses[j].t_ns);
    out.values.push_back(pose_error(Q_ij.inverse() * P_ij, relation));
  }
  return out;
}

}  // namespace hs
