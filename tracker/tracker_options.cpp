#include "tracker/tracker_options.h"

#include <cmath>

#include "common/config/calibration_section.h"
#include "common/config/config_section.h"
#include "common/core/error.h"

namespace hs {
namespace {

void read_orb(ConfigSection& s, OrbOptions& o) {
  s.read("num_features", o.num_features);
  double scale = o.scale_factor;
  s.read("scale_factor", scale);
  o.scale_factor = static_cast<float>(scale);
  s.read("num_levels", o.num_levels);
  s.read("fast_threshold", o.fast_threshold);
  s.read("grid_cols", o.grid_cols);
  s.read("grid_rows", o.grid_rows);
  if (o.num_features < 10 || scale <= 1.0 || o.num_levels < 1 || o.grid_cols < 1 || o.grid_rows < 1)
    s.fail("num_features", "ORB options out of range");
}

void read_direct(ConfigSection& s, DirectOptions& o) {
  s.section("sparse", [&](ConfigSection& c) {
    c.read("coarsest_level", o.sparse.coarsest_level);
    c.read("finest_level", o.sparse.finest_level);
    c.read("max_iterations", o.sparse.max_iterations);
    c.read("huber_k", o.sparse.huber_k);
    c.read("outlier_factor", o.sparse.outlier_factor);
    c.read("min_points", o.sparse.min_points);
    c.read("min_inlier_ratio", o.sparse.min_inlier_ratio);
    c.read("estimate_affine", o.sparse.estimate_affine);
  });
  s.section("patch", [&](ConfigSection& c) {
    c.read("max_iterations", o.patch.max_iterations);
    c.read("max_rms_residual", o.patch.max_rms_residual);
    c.read("capture_radius_px", o.patch.capture_radius_px);
  });
}

void read_pose_opt(ConfigSection& s, PoseOptOptions& o) {
  s.read("rounds", o.rounds);
  s.read("iterations_per_round", o.iterations_per_round);
  s.read("chi2_threshold", o.chi2_threshold);
  s.read("min_inliers", o.min_inliers);
  s.read("max_rms_px", o.max_rms_px);
  if (o.min_inliers < 3) s.fail("min_inliers", "N_min must be at least 3");
}

void read_keyframe(ConfigSection& s, KeyframePolicyOptions& o) {
  s.read("pose_change", o.pose_change);
  s.read("parallax_px", o.parallax_px);
  s.read("min_tracked", o.min_tracked);
  s.read_seconds("min_interval_s", o.min_interval_ns);
  s.read_seconds("max_interval_s", o.max_interval_ns);
  if (o.min_interval_ns < 0 || o.max_interval_ns <= o.min_interval_ns)
    s.fail("max_interval_s", "needs 0 <= min_interval_s < max_interval_s");
}

void read_node(ConfigSection& s, NodeOptions& o) {
  s.read("frame_queue_size", o.frame_queue_size);
  if (o.frame_queue_size < 1) s.fail("frame_queue_size", "must be at least 1");
  s.read("pose_imu_decimation", o.pose_imu_decimation);
  if (o.pose_imu_decimation < 1) s.fail("pose_imu_decimation", "must be at least 1");
  s.read_period("heartbeat_period_s", o.heartbeat_period_ns);
}

}  // namespace

TrackerOptions load_tracker_options(const std::string& path) {
  TrackerOptions o;
  ConfigSection top = ConfigSection::load(path);
  top.section("calibration",
              [&](ConfigSection& s) { read_calibration_section(s, path, o.calib, o.imu.noise); });
  top.section("tracker", [&](ConfigSection& s) {
    std::string rig = o.stereo ? "stereo" : "mono";
    s.read("rig", rig);
    if (rig != "stereo" && rig != "mono") s.fail("rig", "must be 'stereo' or 'mono'");
    o.stereo = rig == "stereo";
    std::string mode = o.descriptors == DescriptorMode::kHybrid ? "hybrid" : "every-frame";
    s.read("descriptors", mode);
    if (mode != "hybrid" && mode != "every-frame")
      s.fail("descriptors", "must be 'hybrid' or 'every-frame'");
    o.descriptors = mode == "hybrid" ? DescriptorMode::kHybrid : DescriptorMode::kEveryFrame;
    s.read("pyramid_levels", o.pyramid_levels);
    if (o.pyramid_levels < 1 || o.pyramid_levels > 6) s.fail("pyramid_levels", "must be 1..6");
    s.read("max_points_per_frame", o.max_points_per_frame);
    s.read("point_grid_px", o.point_grid_px);
    s.read("patch_search_radius_px", o.patch_search_radius_px);
    s.read("init_min_points", o.init_min_points);
    s.read("max_new_points_per_keyframe", o.max_new_points_per_keyframe);
    s.read("new_point_cell_px", o.new_point_cell_px);
    if (o.new_point_cell_px < 4 || o.max_new_points_per_keyframe < 1)
      s.fail("new_point_cell_px", "new point options out of range");
    s.read("reloc_min_inliers", o.reloc_min_inliers);
    s.read_seconds("reinit_after_lost_s", o.reinit_after_lost_ns);
    s.read_seconds("continue_map_within_s", o.continue_map_within_ns);
    s.read_seconds("atlas_wait_s", o.atlas_wait_ns);
    s.read_seconds("max_camera_imu_offset_s", o.max_camera_imu_offset_ns);
    s.read_seconds("max_interpolated_imu_gap_s", o.max_interpolated_imu_gap_ns);
    s.read_seconds("vi_alignment_window_s", o.vi_alignment_window_ns);
    s.read("prior_fading", o.prior_fading);
    if (!(o.prior_fading > 0.0 && o.prior_fading <= 1.0))
      s.fail("prior_fading", "must be in (0, 1]");
    s.read("threads", o.threads);
    if (o.threads < 0) s.fail("threads", "must be >= 0 (0: all cores)");
    s.read("reanchor_every_keyframe", o.reanchor_every_keyframe);
    s.read("local_map_keyframes", o.local_map.max_keyframes);
    s.read("relocalisation_keyframes", o.local_map.max_database_keyframes);
    if (o.max_points_per_frame < 10 || o.point_grid_px < 4 || o.local_map.max_keyframes < 2)
      s.fail("max_points_per_frame", "tracker options out of range");
  });
  top.section("orb", [&](ConfigSection& s) { read_orb(s, o.orb); });
  top.section("stereo_matching", [&](ConfigSection& s) {
    s.read("window", o.stereo_match.window);
    s.read("max_epipolar_px", o.stereo_match.max_epipolar_px);
    s.read("min_depth_m", o.stereo_match.min_depth_m);
    s.read("max_depth_m", o.stereo_match.max_depth_m);
    s.read("refine_slanted", o.stereo_match.refine_slanted);
  });
  top.section("descriptor_matching", [&](ConfigSection& s) {
    s.read("max_distance", o.matching.max_distance);
    double ratio = o.matching.ratio;
    s.read("ratio", ratio);
    o.matching.ratio = static_cast<float>(ratio);
    s.read("search_radius_px", o.matching.search_radius_px);
  });
  top.section("direct", [&](ConfigSection& s) { read_direct(s, o.direct); });
  top.section("pose_optimisation", [&](ConfigSection& s) { read_pose_opt(s, o.pose_opt); });
  top.section("keyframes", [&](ConfigSection& s) { read_keyframe(s, o.keyframe); });
  top.section("mono", [&](ConfigSection& s) {
    MonoOptions& m = o.mono;
    s.read("min_flow_px", m.init.min_flow_px);
    s.read("min_tracked", m.init.min_tracked);
    s.read("initial_median_depth_m", m.initial_median_depth_m);
    s.read_seconds("max_alignment_window_s", m.max_alignment_window_ns);
    s.read_seconds("alignment_spacing_s", m.alignment_spacing_ns);
    s.read("max_scale_sigma", m.alignment.max_scale_sigma);
    s.read("accel_bias_prior_sigma", m.alignment.accel_bias_prior_sigma);
    s.read("vision_position_sigma_m", m.alignment.vision_position_sigma_m);
    s.read_degrees("vision_rotation_sigma_deg", m.alignment.vision_rotation_sigma_rad);
    s.read_degrees("rotation_drift_sigma_deg_s", m.alignment.vision_rotation_drift_sigma);
    s.read_seconds("refine_window_s", m.refine_window_ns);
    s.read_seconds("refine_period_s", m.refine_period_ns);
    s.read("refine_max_scale_sigma", m.refine_max_scale_sigma);
    s.read("point_max_hamming", m.points.max_hamming);
    s.read("point_min_parallax_deg", m.points.min_parallax_deg);
    if (!(m.init.min_flow_px > 0 && m.init.min_tracked >= 8 && m.initial_median_depth_m > 0 &&
          m.alignment.max_scale_sigma > 0 && m.alignment.accel_bias_prior_sigma >= 0 &&
          m.alignment.vision_position_sigma_m > 0 && m.alignment.vision_rotation_sigma_rad > 0 &&
          m.alignment.vision_rotation_drift_sigma >= 0 && m.points.min_parallax_deg > 0 &&
          m.refine_window_ns > 0 && m.refine_period_ns > 0 && m.refine_max_scale_sigma > 0 &&
          m.alignment_spacing_ns > 0))
      s.fail("min_flow_px", "mono options out of range");
  });
  top.section("relocalisation_gate", [&](ConfigSection& s) {
    RelocGateOptions& g = o.reloc_gate;
    s.read("position_m", g.position_m);
    s.read("accel_error_mps2", g.accel_error_mps2);
    s.read_degrees("rotation_deg", g.rotation_rad);
    s.read_seconds("trust_imu_s", g.trust_imu_ns);
    if (g.position_m <= 0 || g.accel_error_mps2 < 0 || g.rotation_rad <= 0)
      s.fail("position_m", "relocalisation gate values must be positive");
  });
  top.section("map_updates", [&](ConfigSection& s) {
    CorrectionOptions& c = o.corrections;
    s.read("max_silent_translation_m", c.max_silent_translation_m);
    s.read_degrees("max_silent_rotation_deg", c.max_silent_rotation_rad);
    if (!(c.max_silent_translation_m >= 0 && c.max_silent_rotation_rad >= 0))
      s.fail("max_silent_translation_m", "must be >= 0");
    s.read_degrees("max_gravity_tilt_deg", c.max_gravity_tilt_rad);
    s.read("max_gravity_magnitude_error", c.max_gravity_magnitude_error);
    if (!(c.max_gravity_tilt_rad >= 0 && c.max_gravity_magnitude_error >= 0))
      s.fail("max_gravity_tilt_deg", "must be >= 0");
  });
  top.section("node", [&](ConfigSection& s) { read_node(s, o.node); });
  o.channels = read_channel_names(top);
  top.finish();
  if (o.mono.max_alignment_window_ns < o.vi_alignment_window_ns)
    throw InputError(path + ": mono.max_alignment_window_s is shorter than vi_alignment_window_s");
  return o;
}

}  // namespace hs
