#pragma once
// Trajectory alignment as evo does it: Umeyama (1991) least squares on positions, with or
// without scale, or origin alignment.
#include <Eigen/Core>
#include <vector>

#include "common/eval/trajectory.h"

namespace hs {

// x -> s * R * x + t.
struct Sim3 {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double s = 1.0;
};

// Minimises sum |dst_i - (s R src_i + t)|^2 (s fixed to 1 unless with_scale). Throws InputError
// when the points are degenerate (fewer than two non-zero singular values of the covariance,
// e.g. all points on a line).
Sim3 umeyama(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst,
             bool with_scale);

enum class AlignMode {
  kNone,
  kSe3,     // Umeyama without scale (evo --align)
  kSim3,    // Umeyama with scale (evo --align --correct_scale), for monocular estimates
  kScale,   // only the Umeyama scale, no rotation or translation (evo --correct_scale alone)
  kOrigin,  // T_gt[0] * T_est[0]^-1 applied on the left (evo --align_origin)
};

// The transform that maps `est` onto `gt` (same length, associated pose by pose).
Sim3 compute_alignment(const Trajectory& gt, const Trajectory& est, AlignMode mode);

// Applies `S` to every pose as evo does: positions p -> s R p + t, orientations R_w_b -> R R_w_b.
void apply_alignment(const Sim3& S, Trajectory& trajectory);

}  // namespace hs
