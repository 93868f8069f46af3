#include "mapper/mapper_options.h"

#include "common/config/calibration_section.h"
#include "common/config/config_section.h"
#include "common/config/process_section.h"

namespace hs {

MapperConfig load_mapper_config(const std::string& path) {
  MapperConfig c;
  MapperOptions& o = c.mapper;
  ConfigSection top = ConfigSection::load(path);
  top.section("calibration", [&](ConfigSection& s) {
    read_calibration_section(s, path, c.calib, o.window.imu.noise);
  });
  top.section("mapper", [&](ConfigSection& s) {
    int window = static_cast<int>(o.graph.window_covisible);
    s.read("window_covisible", window);
    if (window < 1) s.fail("window_covisible", "must be >= 1");
    o.graph.window_covisible = static_cast<size_t>(window);
    s.read("window_min_shared", o.graph.window_min_shared);
    int max_fixed = static_cast<int>(o.graph.max_fixed_keyframes);
    s.read("max_fixed_keyframes", max_fixed);
    if (max_fixed < 0) s.fail("max_fixed_keyframes", "must be >= 0");
    o.graph.max_fixed_keyframes = static_cast<size_t>(max_fixed);
    s.read("pixel_sigma", o.window.pixel_sigma);
    s.read("octave_scale", o.window.octave_scale);
    if (!(o.window.pixel_sigma > 0) || !(o.window.octave_scale >= 1.0))
      s.fail("pixel_sigma", "pixel_sigma must be > 0 and octave_scale >= 1");
    s.read_seconds("max_imu_gap_s", o.window.max_imu_gap_ns);
    s.read_degrees("window_gravity_deg", o.window_gravity_sigma_rad);
    if (!(o.window_gravity_sigma_rad >= 0)) s.fail("window_gravity_deg", "must be >= 0");
    s.read_degrees("window_gravity_mono_deg", o.window_gravity_mono_sigma_rad);
    if (!(o.window_gravity_mono_sigma_rad >= 0)) s.fail("window_gravity_mono_deg", "must be >= 0");
    s.read("point_outlier_ratio", o.point_outlier_ratio);
    if (!(o.point_outlier_ratio > 0 && o.point_outlier_ratio <= 1))
      s.fail("point_outlier_ratio", "must be in (0, 1]");
    s.read("cull_keyframes", o.cull_keyframes);
    s.read("far_point_disparity_px", o.far_point_disparity_px);
    if (!(o.far_point_disparity_px >= 0)) s.fail("far_point_disparity_px", "must be >= 0");
  });
  top.section("local_ba", [&](ConfigSection& s) {
    LocalBaOptions& b = o.ba;
    s.read("iterations_per_round", b.iterations_per_round);
    s.read("function_tolerance", b.function_tolerance);
    s.read("screening_function_tolerance", b.screening_function_tolerance);
    if (!(b.function_tolerance > 0 && b.function_tolerance < 1))
      s.fail("function_tolerance", "must be in (0, 1)");
    if (!(b.screening_function_tolerance > 0 && b.screening_function_tolerance < 1))
      s.fail("screening_function_tolerance", "must be in (0, 1)");
    s.read("reject_outliers", b.reject_outliers);
    std::string solver = b.solver == LocalBaOptions::Solver::kCeres ? "ceres" : "schur_lm";
    s.read("solver", solver);
    if (solver != "ceres" && solver != "schur_lm")
      s.fail("solver", "must be ceres or schur_lm, not '" + solver + "'");
    b.solver =
        solver == "ceres" ? LocalBaOptions::Solver::kCeres : LocalBaOptions::Solver::kSchurLm;
    s.read("time_budget_ms", b.time_budget_ms);
    s.read("chi2_threshold", b.chi2_threshold);
    s.read("min_depth_m", b.min_depth_m);
    if (b.iterations_per_round < 1 || !(b.time_budget_ms > 0) || !(b.chi2_threshold > 0))
      s.fail("iterations_per_round", "local BA options out of range");
  });
  top.section("inertial", [&](ConfigSection& s) {
    InertialRefinementOptions& r = o.inertial;
    s.read("every_keyframes", r.every_keyframes);
    int max_kf = static_cast<int>(r.max_keyframes), min_kf = static_cast<int>(r.min_keyframes);
    s.read("max_keyframes", max_kf);
    s.read("min_keyframes", min_kf);
    s.read_degrees("gravity_prior_deg", r.gravity_prior_sigma_rad);
    s.read_degrees("max_tilt_deg", r.max_tilt_rad);
    if (r.every_keyframes < 0 || min_kf < 2 || max_kf < min_kf ||
        !(r.gravity_prior_sigma_rad > 0) || !(r.max_tilt_rad > 0))
      s.fail("every_keyframes", "inertial refinement options out of range");
    r.max_keyframes = static_cast<size_t>(max_kf);
    r.min_keyframes = static_cast<size_t>(min_kf);
  });
  top.section("new_points", [&](ConfigSection& s) {
    NewPointOptions& n = o.new_points;
    int covisible = static_cast<int>(n.covisible_keyframes);
    s.read("covisible_keyframes", covisible);
    s.read("max_hamming", n.max_hamming);
    s.read("ratio", n.ratio);
    s.read("epipolar_px", n.epipolar_px);
    s.read("min_parallax_deg", n.min_parallax_deg);
    s.read("max_reprojection_px", n.max_reprojection_px);
    s.read("scale_ratio_factor", n.scale_ratio_factor);
    s.read("pixel_sigma", o.window.detected_pixel_sigma);
    if (covisible < 0 || n.max_hamming < 0 || n.max_hamming > 256 ||
        !(n.ratio > 0 && n.ratio <= 1) || !(n.epipolar_px > 0) || !(n.min_parallax_deg >= 0) ||
        !(n.max_reprojection_px > 0) || !(n.scale_ratio_factor >= 1) ||
        !(o.window.detected_pixel_sigma > 0))
      s.fail("covisible_keyframes", "new point options out of range");
    n.covisible_keyframes = static_cast<size_t>(covisible);
    n.octave_scale = o.window.octave_scale;
  });
  top.section("culling", [&](ConfigSection& s) {
    CullingOptions& k = o.culling;
    s.read("redundant_ratio", k.redundant_ratio);
    s.read("min_observers", k.min_observers);
    s.read("octave_slack", k.octave_slack);
    int keep = static_cast<int>(k.keep_recent);
    s.read("keep_recent", keep);
    if (keep < 0 || k.min_observers < 1 || !(k.redundant_ratio > 0 && k.redundant_ratio <= 1))
      s.fail("redundant_ratio", "culling options out of range");
    k.keep_recent = static_cast<size_t>(keep);
    s.read_seconds("max_imu_span_s", k.max_imu_span_ns);
  });
  top.section("loop", [&](ConfigSection& s) {
    LoopDetectionOptions& l = o.loop;
    s.read("enabled", l.enabled);
    s.read("index_tables", l.index.tables);
    int candidates = static_cast<int>(l.candidates);
    s.read("candidates", candidates);
    s.read("min_age_s", l.min_age_s);
    s.read("max_hamming", l.verify.max_hamming);
    s.read("ratio", l.verify.ratio);
    s.read("min_inliers", l.verify.min_inliers);
    s.read("drift_base_m", l.drift_base_m);
    s.read("drift_per_m", l.drift_per_m);
    s.read_degrees("drift_base_deg", l.drift_base_rad);
    s.read_degrees("drift_deg_per_m", l.drift_rad_per_m);
    s.read_degrees("max_tilt_deg", l.max_tilt_rad);
    s.read("consistent", l.consistent);
    s.read("merge_worlds", l.merge_worlds);
    s.read("merge_in_run_m", l.merge_in_run_m);
    s.read_degrees("merge_in_run_deg", l.merge_in_run_rad);
    if (l.index.tables < 1 || l.index.tables > 16 || candidates < 1 || !(l.min_age_s >= 0) ||
        l.verify.max_hamming < 0 || l.verify.max_hamming > 256 ||
        !(l.verify.ratio > 0 && l.verify.ratio <= 1) || l.verify.min_inliers < 6 ||
        !(l.drift_base_m >= 0) || !(l.drift_per_m >= 0) || !(l.drift_base_rad >= 0) ||
        !(l.drift_rad_per_m >= 0) || !(l.max_tilt_rad >= 0) || l.consistent < 1 ||
        !(l.merge_in_run_m >= 0) || !(l.merge_in_run_rad >= 0))
      s.fail("enabled", "loop options out of range");
    l.candidates = static_cast<size_t>(candidates);
    l.verify.octave_scale = o.window.octave_scale;
  });
  top.section("loop_closing", [&](ConfigSection& s) {
    LoopClosingOptions& l = o.loop_closing;
    s.read("enabled", l.enabled);
    s.read("min_correction_m", l.min_correction_m);
    s.read_degrees("min_correction_deg", l.min_correction_rad);
    s.read("min_keyframes_between", l.min_keyframes_between);
    s.read("strong_covisibility", l.strong_covisibility);
    s.read("loop_weight", l.loop_weight);
    s.read("four_dof", l.pose_graph.four_dof);
    int points = static_cast<int>(o.loop_correction_point_keyframes);
    s.read("correction_point_keyframes", points);
    if (!(l.min_correction_m >= 0) || !(l.min_correction_rad >= 0) || l.min_keyframes_between < 0 ||
        l.strong_covisibility < 1 || !(l.loop_weight > 0) || points < 1)
      s.fail("enabled", "loop closing options out of range");
    o.loop_correction_point_keyframes = static_cast<size_t>(points);
  });
  top.section("full_ba", [&](ConfigSection& s) {
    FullBaOptions& f = o.full_ba;
    s.read("enabled", f.enabled);
    s.read("background", f.background);
    s.read("every_keyframes", f.every_keyframes);
    s.read("iterations_per_round", f.iterations_per_round);
    s.read("time_budget_ms", f.time_budget_ms);
    s.read("far_point_disparity_px", f.far_point_disparity_px);
    if (f.iterations_per_round < 1 || f.every_keyframes < 0 || !(f.time_budget_ms > 0) ||
        !(f.far_point_disparity_px >= 0))
      s.fail("enabled", "full BA options out of range");
  });
  top.section("fusion", [&](ConfigSection& s) {
    PointFusionOptions& f = o.fusion;
    s.read("enabled", o.fuse_revisits);
    s.read("max_hamming", f.max_hamming);
    s.read("ratio", f.ratio);
    s.read("radius_px", f.radius_px);
    s.read("max_depth_error", f.max_depth_error);
    int revisited = static_cast<int>(f.revisited_keyframes);
    int neighbourhood = static_cast<int>(f.neighbourhood_keyframes);
    s.read("revisited_keyframes", revisited);
    s.read("neighbourhood_keyframes", neighbourhood);
    if (f.max_hamming < 0 || f.max_hamming > 256 || !(f.ratio > 0 && f.ratio <= 1) ||
        !(f.radius_px > 0) || !(f.max_depth_error >= 0) || revisited < 1 || neighbourhood < 0)
      s.fail("enabled", "fusion options out of range");
    f.revisited_keyframes = static_cast<size_t>(revisited);
    f.neighbourhood_keyframes = static_cast<size_t>(neighbourhood);
  });
  top.section("localisation", [&](ConfigSection& s) { s.read("only", o.localisation_only); });
  read_process_tail(top, c.heartbeat_period_ns, c.channels);
  return c;
}

}  // namespace hs
