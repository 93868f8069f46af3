#pragma once
// Absolute and relative pose errors with evo's definitions (evo/core/metrics.py).
//
// APE: E_i = P_i^-1 Q_i (P estimate, Q ground truth, after alignment).
// RPE: E_ij = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j).
// Per-pair error for each relation:
//   kTransPart: APE |t(P_i) - t(Q_i)| (evo's default, the usual "ATE"); RPE |t(E_ij)|
//   kRotPart:   |R(E) - I|_F
//   kFull:      |E - I_4|_F (evo's "full transformation"; NOT the paper's |log(E)^v|_2, which
//               evo does not compute, though both are 0 exactly when E = I)
//   kAngleRad / kAngleDeg: the rotation angle of R(E), |log(R(E))^v|
// The HS-SLAM paper's tables report the translation part, i.e. kTransPart.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "common/eval/trajectory.h"

namespace hs {

enum class PoseRelation { kTransPart, kRotPart, kFull, kAngleDeg, kAngleRad };

// Accepts evo's names (trans_part, rot_part, full, angle_deg, angle_rad) and the aliases
// "trans" and "rot_angle_deg"; throws InputError otherwise.
PoseRelation parse_pose_relation(const std::string& name);
const char* relation_name(PoseRelation relation);   // evo's name, e.g. "trans_part"
const char* relation_title(PoseRelation relation);  // e.g. "translation part"
const char* relation_unit(PoseRelation relation);   // "m", "deg", "rad" or "" (unitless)

// One error value per pose (APE) or pose pair (RPE), stamped with the estimate's time of the
// pose (APE) or of the pair's second pose (RPE, as evo plots it).
struct ErrorSeries {
  std::vector<int64_t> t_ns;
  std::vector<double> values;
};

// gt and est associated pose by pose (same length).
ErrorSeries compute_ape(const Trajectory& gt, const Trajectory& est, PoseRelation relation);

enum class DeltaUnit { kFrames, kMeters };

using IndexPair = std::pair<size_t, size_t>;

// evo's id_pairs_from_delta on the estimate's poses (evo's default, pairs_from_reference off):
// frames: (0,d),(d,2d),... or, with all_pairs, (i,i+d) for every i.
// meters: consecutive pairs between the poses where the travelled path since the previous one
// reaches delta (the first such pose after the start opens the first pair); with all_pairs, for
// every i the j > i whose path length from i is nearest delta, kept if within
// rel_delta_tol * delta. Throws InputError when no pair results.
std::vector<IndexPair> rpe_pairs(const Trajectory& est, double delta, DeltaUnit unit,
                                 bool all_pairs, double rel_delta_tol = 0.1);

ErrorSeries compute_rpe(const Trajectory& gt, const Trajectory& est,
                        const std::vector<IndexPair>& pairs, PoseRelation relation);

}  // namespace hs
