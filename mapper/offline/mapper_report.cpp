#include "mapper/offline/mapper_report.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <numeric>
#include <sstream>

#include "common/core/atomic_file.h"
#include "common/core/error.h"
#include "mapper/keyframe_from_msg.h"
#include "tracker/offline/run_report.h"

namespace hs {

void MapperRunStats::add(const MapperStep& step) {
  if (step.inertial) inertial_ms.push_back(step.inertial->time_ms);
  if (step.loop_query) loop_query_ms.push_back(step.loop_query->time_ms);
  if (step.loop) loops.push_back(*step.loop);
  if (step.closure) pose_graph_ms.push_back(step.closure->graph.time_ms);
  if (step.full_ba) {
    full_ba_ms.push_back(step.full_ba->time_ms);
    full_ba_keyframes.push_back(step.full_ba_applied.keyframes);
    full_ba_points.push_back(step.full_ba_applied.points);
    full_ba_moved.push_back(step.full_ba_applied.keyframes_moved);
  }
  if (step.ba.rounds == 0) return;
  ba_ms.push_back(step.ba.time_ms);
  ba_cpu_ms.push_back(step.ba.cpu_ms);
  window_keyframes.push_back(step.window_keyframes);
  window_points.push_back(step.window_points);
  window_observations.push_back(step.window_observations);
  ba_iterations.push_back(step.ba.iterations);
}

MapperOptions reproducible(MapperOptions options) {
  options.ba.time_budget_ms = std::numeric_limits<double>::infinity();
  options.full_ba.time_budget_ms = std::numeric_limits<double>::infinity();
  options.full_ba.background = false;
  return options;
}

BackEnd in_process_back_end(Mapper& mapper, MapperRunStats& stats, bool verbose) {
  return [&mapper, &stats, verbose](const hsslam::keyframe_t& msg) {
    MapperStep step = mapper.add_keyframe(keyframe_from_msg(msg, "KEYFRAME"));
    stats.add(step);
    if (verbose && !step.message.empty()) std::cerr << "mapper: " << step.message << "\n";
    std::vector<MapCorrection> out;
    if (step.correction) out.push_back(std::move(*step.correction));
    return out;
  };
}

AtlasBackEnd in_process_atlas(Mapper& mapper) {
  return [&mapper](const hsslam::reloc_request_t& msg) {
    const RelocRequest q = reloc_request_from_msg(msg, "RELOC_REQUEST");
    return mapper.relocalise(q.frame, q.seq, q.next_map_id);
  };
}

void finish_back_end(Mapper& mapper, MapperRunStats& stats) {
  stats.add(mapper.finish_full_ba(true));
}

void write_loops_csv(const std::string& path, const MapperRunStats& stats) {
  std::ostringstream o;
  o << "# query_t_ns,candidate_t_ns,x,y,z,qx,qy,qz,qw,inliers,path_m,correction_m,correction_deg\n";
  o.precision(9);
  for (const LoopFound& l : stats.loops) {
    const Eigen::Quaterniond q(l.T_c_q.linear());
    const Eigen::Vector3d& t = l.T_c_q.translation();
    o << l.query_t_ns << "," << l.candidate_t_ns << "," << t.x() << "," << t.y() << "," << t.z()
      << "," << q.x() << "," << q.y() << "," << q.z() << "," << q.w() << "," << l.inliers << ","
      << l.path_m << "," << l.drift.translation().norm() << ","
      << Eigen::AngleAxisd(l.drift.linear()).angle() * 180.0 / M_PI << "\n";
  }
  write_file_atomically(path, o.str());
}

std::string final_trajectory_text(const std::string& out_dir, const OfflineRunResult& result,
                                  const Mapper& mapper) {
  const Trajectory final_est =
      result.keyframe_relative_estimate([&mapper](int64_t id) { return mapper.keyframe_pose(id); });
  save_tum(out_dir + "/trajectory_final.tum", final_est);
  std::ostringstream o;
  o << "final trajectory (frames on the mapper's keyframe poses): " << out_dir
    << "/trajectory_final.tum";
  try {
    if (const auto eval = evaluate_run(result, final_est)) {
      o.precision(4);
      o << ", ATE RMSE " << eval->ape.stats.rmse * 100 << " cm (online "
        << evaluate_run(result)->ape.stats.rmse * 100 << " cm)";
    }
  } catch (const InputError& e) {
    o << " (no evaluation: " << e.what() << ")";
  }
  return o.str() + "\n";
}

std::string mapper_text(const MapperRunStats& stats, const Mapper& mapper,
                        const OfflineRunResult& result) {
  const MapperCounters& counters = mapper.counters();
  const auto mean = [](const std::vector<double>& v) {
    return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / v.size();
  };
  std::vector<double> shifts_mm;
  int corrections = 0;
  for (const FrameRecord& f : result.frames) {
    corrections += f.corrections;
    if (f.corrections > 0) shifts_mm.push_back(1e3 * f.correction_shift_m);
  }
  const TimeStats ba = time_stats(stats.ba_ms);
  const TimeStats shift = time_stats(shifts_mm);
  std::ostringstream o;
  o.precision(3);
  o << "mapper: " << counters.keyframes << " keyframes, " << counters.local_ba_runs
    << " local BAs (median " << ba.median << " ms, p95 " << ba.p95 << " ms, max " << ba.max
    << " ms; CPU median " << time_stats(stats.ba_cpu_ms).median << " ms; "
    << mean(stats.ba_iterations) << " iterations; window " << mean(stats.window_keyframes)
    << " keyframes, " << mean(stats.window_points) << " points, " << mean(stats.window_observations)
    << " reprojection terms), new points " << counters.new_points << ", culled keyframes "
    << counters.culled_keyframes << ", removed points " << counters.removed_points
    << ", IMU factors skipped (gaps) " << counters.imu_factors_skipped << "; inertial refinements "
    << counters.inertial_refinements << " (not adopted " << counters.inertial_refinements_rejected
    << ", median " << time_stats(stats.inertial_ms).median << " ms); gravity "
    << gravity_tilt_rad(mapper.gravity_w()) * 180.0 / M_PI << " deg from the tracker world's -z\n";
  o << "loops: " << counters.loops_detected << " detected (" << counters.loops_closed
    << " closed) in " << counters.loop_queries << " queries (places verified "
    << counters.places_verified << ", implausible drift " << counters.places_implausible
    << ", neighbourhood disagreed " << counters.places_unconfirmed << "; query median "
    << time_stats(stats.loop_query_ms).median << " ms, p95 " << time_stats(stats.loop_query_ms).p95
    << " ms; index " << mapper.loop_index_bytes() / 1e6 << " MB); maps merged "
    << counters.maps_merged << ", points fused " << counters.points_fused << " ("
    << counters.points_fused_as_ties << " across a closed loop)"
    << ", observations found again " << counters.fusion_observations
    << "; lost frames placed by the atlas " << counters.relocalisations << " of "
    << counters.reloc_requests << " asked\n";
  o << "full BA: " << counters.full_bas << " applied (" << counters.full_bas_discarded
    << " discarded), median " << time_stats(stats.full_ba_ms).median << " ms over "
    << mean(stats.full_ba_keyframes) << " keyframes, " << mean(stats.full_ba_points) << " points\n";
  o << "corrections applied " << corrections << ": pose moved median " << shift.median
    << " mm, p95 " << shift.p95 << " mm, max " << shift.max << " mm; ignored "
    << result.counters.corrections_ignored << ", stated jumps (new map id) "
    << result.counters.correction_jumps << "\n";
  return o.str();
}

}  // namespace hs
