#pragma once
// One evaluation run, evo_ape + evo_rpe in one: associate, optionally align, then APE with the
// chosen pose relation and RPE translation part (m) and rotation angle (deg).
#include <Eigen/Geometry>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "common/eval/align.h"
#include "common/eval/associate.h"
#include "common/eval/metrics.h"
#include "common/eval/stats.h"
#include "common/eval/trajectory.h"

namespace hs {

struct EvalOptions {
  int64_t t_max_diff_ns = 10'000'000;  // evo --t_max_diff 0.01
  int64_t t_offset_ns = 0;             // added to the estimate's stamps (evo --t_offset)
  AlignMode align = AlignMode::kNone;
  PoseRelation ape_relation = PoseRelation::kTransPart;
  double rpe_delta = 1.0;
  DeltaUnit rpe_delta_unit = DeltaUnit::kFrames;
  bool rpe_all_pairs = false;
  double rpe_rel_delta_tol = 0.1;  // only for metres with all pairs, as in evo
  // If set, the estimate holds camera poses T_w_c (T_b_c = EuRoC's T_BS of that camera, p_b =
  // T_b_c p_c). The alignment is fitted between camera poses (ground truth moved to the camera
  // as T_w_b * T_b_c), so a Sim(3) scale is found before the metric lever arm is used; errors
  // are then measured between body poses, the aligned estimate becoming T_w_c * T_b_c^-1.
  std::optional<Eigen::Isometry3d> T_b_c;
};

struct ErrorResult {
  PoseRelation relation = PoseRelation::kTransPart;
  ErrorSeries series;
  Stats stats;
};

struct EvalResult {
  EvalOptions options;
  size_t gt_poses = 0, est_poses = 0;
  Association matched;  // matched.est is in the body frame and aligned
  Sim3 alignment;
  ErrorResult ape, rpe_trans, rpe_rot;
};

// Throws InputError when nothing matches, alignment is degenerate or RPE has no pairs.
EvalResult evaluate(const Trajectory& gt, const Trajectory& est, const EvalOptions& options);

// Human-readable report in evo's layout.
std::string summary_text(const EvalResult& result);

// {"matched", "alignment": {...}, "ape": {...}, "rpe_trans": {...}, "rpe_rot": {...}, ...}
nlohmann::json to_json(const EvalResult& result);

const char* align_mode_name(AlignMode mode);  // "none", "se3", "sim3", "scale", "origin"

}  // namespace hs
