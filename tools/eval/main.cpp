// hs-eval: trajectory accuracy as evo_ape / evo_rpe define it (see --help).
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "common/core/atomic_file.h"
#include "common/core/error.h"
#include "common/core/types.h"
#include "common/eval/evaluate.h"
#include "common/eval/extrinsics.h"
#include "common/eval/plot.h"

namespace {

constexpr const char* kFooter = R"(
Definitions (as evo 1.x, evo/core/metrics.py):
  association  each pose of the shorter trajectory (the estimate if equally long) is paired
               with the nearest-in-time pose of the other; estimate stamps + t-offset; pairs
               further apart than t-max-diff are dropped.
  alignment    Umeyama least squares on the matched positions, mapping estimate onto ground
               truth: --align SE(3), --align --correct-scale Sim(3) (monocular), --correct-scale
               alone only the scale, --align-origin T_gt[0] * T_est[0]^-1.
  APE          E_i = P_i^-1 Q_i (P estimate, Q ground truth). trans_part: |t(P_i) - t(Q_i)|
               (evo's default, the usual ATE); rot_part: |R(E)-I|_F; full: |E - I|_F (evo's
               "full transformation" uses this Frobenius norm, not the paper's |log(E)^v|_2,
               which no evo relation computes); angle_deg/angle_rad: rotation angle of E.
               The paper's Tables 2 and 3 report the translational component = trans_part.
  RPE          E_ij = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j) on pairs chosen on the estimate: frames
               (0,d),(d,2d),... (or every (i,i+d) with --all-pairs); metres: between poses
               where the travelled path reaches d. Reported as translation part (m) and
               rotation angle (deg).
  statistics   rmse, mean, median, std (population, numpy ddof=0: evo's S.D.), min, max, sse.
  --T-b-c      the estimate holds camera poses T_w_c. T_b_c maps camera points into the
               body frame (p_b = T_b_c p_c), i.e. EuRoC's T_BS of that camera: give the
               camera's sensor.yaml or its 16 row-major entries. The alignment is fitted
               between camera poses (ground truth moved to the camera: T_w_b * T_b_c), so a
               monocular scale is found before the metric lever arm is used; all errors are
               then measured between body poses, the aligned estimate becoming
               T_w_b = T_w_c * T_b_c^-1 (without alignment, simply that conversion).
Exit status: 0 on success; 1 on bad input or unwritable output (the message names the file
and line); CLI11's usage codes (> 1) on a malformed command line.)";

// Seconds from the command line as ns; throws unless finite and within +-1e6 s (so stamp
// arithmetic cannot overflow).
int64_t option_ns(double t_s, const std::string& name) {
  if (!std::isfinite(t_s) || std::abs(t_s) > 1e6) throw hs::InputError(name, "out of range");
  return hs::s_to_ns(t_s);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hs-eval: absolute and relative pose error of an estimated trajectory"};
  app.footer(kFooter);
  std::string gt_path, est_path, format = "auto", gt_format, est_format;
  std::string relation = "trans_part", delta_unit = "f";
  std::string json_path, plot_path, aligned_path;
  std::vector<std::string> T_b_c_args;
  double t_max_diff_s = 0.01, t_offset_s = 0.0;
  bool align = false, correct_scale = false, align_origin = false;
  hs::EvalOptions opt;

  app.add_option("ground_truth", gt_path, "ground-truth trajectory (TUM or EuRoC csv)")->required();
  app.add_option("estimate", est_path, "estimated trajectory (TUM or EuRoC csv)")->required();
  app.add_option("--format", format,
                 "format of both files: auto (',' in the first data line ="
                 " EuRoC csv, else TUM), tum, euroc")
      ->capture_default_str();
  app.add_option("--gt-format", gt_format, "format of the ground truth (overrides --format)");
  app.add_option("--est-format", est_format, "format of the estimate (overrides --format)");
  app.add_option("--t-max-diff", t_max_diff_s, "max. time difference for association [s]")
      ->capture_default_str();
  app.add_option("--t-offset", t_offset_s, "time offset added to the estimate's stamps [s]")
      ->capture_default_str();
  auto* align_flag = app.add_flag("-a,--align", align, "Umeyama SE(3) alignment");
  app.add_flag("-s,--correct-scale", correct_scale,
               "with --align: Sim(3) alignment; alone: scale only");
  app.add_flag("--align-origin", align_origin, "align the first poses")->excludes(align_flag);
  app.add_option("-r,--pose-relation", relation,
                 "APE pose relation: trans_part (alias trans), rot_part, full, angle_deg "
                 "(alias rot_angle_deg), angle_rad")
      ->capture_default_str();
  app.add_option("-d,--delta", opt.rpe_delta, "RPE delta")->capture_default_str();
  app.add_option("-u,--delta-unit", delta_unit, "RPE delta unit: f (frames) or m (metres)")
      ->check(CLI::IsMember({"f", "m"}))
      ->capture_default_str();
  app.add_flag("--all-pairs", opt.rpe_all_pairs, "RPE over all pairs, not consecutive ones");
  app.add_option("--rel-delta-tol", opt.rpe_rel_delta_tol,
                 "relative delta tolerance for --all-pairs with metres")
      ->capture_default_str();
  app.add_option("--T-b-c", T_b_c_args,
                 "body<-camera transform: sensor.yaml path or 16 numbers, given after the two "
                 "files (see below)")
      ->expected(1, 16);
  app.add_option("--json", json_path, "write a JSON summary here");
  app.add_option("--plot", plot_path, "write a PNG plot here");
  app.add_option("--save-aligned", aligned_path, "write the matched, aligned estimate (TUM)");
  CLI11_PARSE(app, argc, argv);

  try {
    const hs::TrajectoryFormat fallback = hs::parse_trajectory_format(format);
    const hs::TrajectoryFormat gt_fmt =
        gt_format.empty() ? fallback : hs::parse_trajectory_format(gt_format);
    const hs::TrajectoryFormat est_fmt =
        est_format.empty() ? fallback : hs::parse_trajectory_format(est_format);
    opt.t_max_diff_ns = option_ns(t_max_diff_s, "--t-max-diff");
    opt.t_offset_ns = option_ns(t_offset_s, "--t-offset");
    opt.ape_relation = hs::parse_pose_relation(relation);
    opt.rpe_delta_unit = delta_unit == "m" ? hs::DeltaUnit::kMeters : hs::DeltaUnit::kFrames;
    opt.align = align           ? (correct_scale ? hs::AlignMode::kSim3 : hs::AlignMode::kSe3)
                : correct_scale ? hs::AlignMode::kScale
                : align_origin  ? hs::AlignMode::kOrigin
                                : hs::AlignMode::kNone;
    if (!T_b_c_args.empty()) opt.T_b_c = hs::parse_T_b_c(T_b_c_args);

    const hs::Trajectory gt = hs::load_trajectory(gt_path, gt_fmt);
    const hs::Trajectory est = hs::load_trajectory(est_path, est_fmt);
    const hs::EvalResult result = hs::evaluate(gt, est, opt);

    std::cout << "ground truth: " << gt_path << "\nestimate:     " << est_path << "\n"
              << hs::summary_text(result);
    if (!json_path.empty()) {
      nlohmann::json j = hs::to_json(result);
      j["ground_truth"] = gt_path;
      j["estimate"] = est_path;
      hs::write_file_atomically(json_path, j.dump(2) + "\n");
    }
    if (!plot_path.empty()) hs::write_plot(plot_path, result, "hs-eval: " + est_path);
    if (!aligned_path.empty()) hs::save_tum(aligned_path, result.matched.est);
  } catch (const hs::InputError& e) {
    std::fprintf(stderr, "hs-eval: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
