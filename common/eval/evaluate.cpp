#include "common/eval/evaluate.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace hs {
namespace {

ErrorResult make_result(PoseRelation relation, ErrorSeries series) {
  ErrorResult r;
  r.relation = relation;
  r.stats = compute_stats(series.values);
  r.series = std::move(series);
  return r;
}

// Every pose T_w_x becomes T_w_x * T_x_y.
Trajectory right_multiplied(Trajectory t, const Eigen::Isometry3d& T_x_y) {
  for (StampedPose& pose : t.poses) pose.T_w_b = pose.T_w_b * T_x_y;
  return t;
}

std::string rpe_title(const EvalResult& r, const ErrorResult& e) {
  const EvalOptions& o = r.options;
  std::ostringstream s;
  s << "RPE w.r.t. " << relation_title(e.relation) << " (" << relation_unit(e.relation)
    << ") for delta = " << o.rpe_delta
    << (o.rpe_delta_unit == DeltaUnit::kFrames ? " (frames)" : " (m)")
    << (o.rpe_all_pairs ? " using all pairs" : " using consecutive pairs");
  return s.str();
}

std::string ape_title(const ErrorResult& e) {
  const std::string unit = relation_unit(e.relation);
  return std::string("APE w.r.t. ") + relation_title(e.relation) +
         (unit.empty() ? " (unit-less)" : " (" + unit + ")");
}

void append_stats(std::ostringstream& out, const std::string& title, const Stats& s) {
  char buf[512];
  std::snprintf(buf, sizeof(buf),
                "%s\n       max\t%.6f\n      mean\t%.6f\n    median\t%.6f\n       min\t%.6f\n"
                "      rmse\t%.6f\n       sse\t%.6f\n       std\t%.6f\n     count\t%zu\n\n",
                title.c_str(), s.max, s.mean, s.median, s.min, s.rmse, s.sse, s.std, s.count);
  out << buf;
}

nlohmann::json stats_json(const ErrorResult& e) {
  const Stats& s = e.stats;
  return {{"pose_relation", relation_name(e.relation)},
          {"unit", relation_unit(e.relation)},
          {"rmse", s.rmse},
          {"mean", s.mean},
          {"median", s.median},
          {"std", s.std},
          {"min", s.min},
          {"max", s.max},
          {"sse", s.sse},
          {"count", s.count}};
}

}  // namespace

const char* align_mode_name(AlignMode mode) {
  switch (mode) {
    case AlignMode::kNone:
      return "none";
    case AlignMode::kSe3:
      return "se3";
    case AlignMode::kSim3:
      return "sim3";
    case AlignMode::kScale:
      return "scale";
    case AlignMode::kOrigin:
      return "origin";
  }
  return "";
}

EvalResult evaluate(const Trajectory& gt, const Trajectory& est, const EvalOptions& options) {
  EvalResult r;
  r.options = options;
  r.gt_poses = gt.poses.size();
  r.est_poses = est.poses.size();
  r.matched = associate(gt, est, options.t_max_diff_ns, options.t_offset_ns);
  if (options.T_b_c) {
    const Trajectory gt_c = right_multiplied(r.matched.gt, *options.T_b_c);
    r.alignment = compute_alignment(gt_c, r.matched.est, options.align);
    apply_alignment(r.alignment, r.matched.est);
    r.matched.est = right_multiplied(r.matched.est, options.T_b_c->inverse());
  } else {
    r.alignment = compute_alignment(r.matched.gt, r.matched.est, options.align);
    apply_alignment(r.alignment, r.matched.est);
  }

  const Trajectory& q = r.matched.gt;
  const Trajectory& p = r.matched.est;
  r.ape = make_result(options.ape_relation, compute_ape(q, p, options.ape_relation));
  const std::vector<IndexPair> pairs = rpe_pairs(p, options.rpe_delta, options.rpe_delta_unit,
                                                 options.rpe_all_pairs, options.rpe_rel_delta_tol);
  r.rpe_trans =
      make_result(PoseRelation::kTransPart, compute_rpe(q, p, pairs, PoseRelation::kTransPart));
  r.rpe_rot =
      make_result(PoseRelation::kAngleDeg, compute_rpe(q, p, pairs, PoseRelation::kAngleDeg));
  return r;
}

std::string summary_text(const EvalResult& r) {
  std::ostringstream out;
  const EvalOptions& o = r.options;
  char buf[256];
  std::snprintf(buf, sizeof(buf),
                "matched %zu of max. %zu pose pairs (estimate %zu poses, ground truth %zu; "
                "max diff %.4f s, offset %.4f s)\n",
                r.matched.est.poses.size(), std::min(r.est_poses, r.gt_poses), r.est_poses,
                r.gt_poses, o.t_max_diff_ns * 1e-9, o.t_offset_ns * 1e-9);
  out << buf;
  std::snprintf(buf, sizeof(buf), "alignment: %s, scale %.6f\n\n", align_mode_name(o.align),
                r.alignment.s);
  out << buf;
  append_stats(out, ape_title(r.ape), r.ape.stats);
  append_stats(out, rpe_title(r, r.rpe_trans), r.rpe_trans.stats);
  append_stats(out, rpe_title(r, r.rpe_rot), r.rpe_rot.stats);
  return out.str();
}

nlohmann::json to_json(const EvalResult& r) {
  const EvalOptions& o = r.options;
  nlohmann::json rotation = nlohmann::json::array();
  for (int i = 0; i < 3; ++i)
    rotation.push_back({r.alignment.R(i, 0), r.alignment.R(i, 1), r.alignment.R(i, 2)});
  nlohmann::json j;
  j["ground_truth_poses"] = r.gt_poses;
  j["estimate_poses"] = r.est_poses;
  j["matched"] = r.matched.est.poses.size();
  j["t_max_diff_s"] = o.t_max_diff_ns * 1e-9;
  j["t_offset_s"] = o.t_offset_ns * 1e-9;
  j["T_b_c_applied"] = o.T_b_c.has_value();
  j["alignment"] = {{"mode", align_mode_name(o.align)},
                    {"scale", r.alignment.s},
                    {"rotation", rotation},
                    {"translation", {r.alignment.t.x(), r.alignment.t.y(), r.alignment.t.z()}}};
  j["ape"] = stats_json(r.ape);
  nlohmann::json rpe = {{"delta", o.rpe_delta},
                        {"delta_unit", o.rpe_delta_unit == DeltaUnit::kFrames ? "f" : "m"},
                        {"all_pairs", o.rpe_all_pairs}};
  j["rpe_trans"] = stats_json(r.rpe_trans);
  j["rpe_trans"].update(rpe);
  j["rpe_rot"] = stats_json(r.rpe_rot);
  j["rpe_rot"].update(rpe);
  return j;
}

}  // namespace hs
