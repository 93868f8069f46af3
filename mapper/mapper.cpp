#include "mapper/mapper.h"

#include <algorithm>
#include <chrono>
#include <set>
#include <stdexcept>
#include <unordered_map>
#include <utility>

namespace hs {
namespace {

void add_message(MapperStep& step, const std::string& text) {
  step.message += (step.message.empty() ? "" : "; ") + text;
}

}  // namespace

Mapper::Mapper(const StereoCalib& calib, const MapperOptions& options)
    : options_(options),
      calib_(calib),
      graph_(options.graph),
      ba_(calib, options.ba),
      full_ba_solver_(calib,
                      [&] {
                        LocalBaOptions o = options.ba;
                        o.iterations_per_round = options.full_ba.iterations_per_round;
                        o.time_budget_ms = options.full_ba.time_budget_ms;
                        o.sparse = true;
                        return o;
                      }()),
      loops_(calib, options.loop) {
  const auto far_m = [&](double disparity_px) {
    return disparity_px > 0 ? calib.cam0.intrinsics.fx * calib.baseline() / disparity_px : 0.0;
  };
  options_.window.fixed_point_distance_m = far_m(options_.far_point_disparity_px);
  full_ba_window_ = options_.window;
  full_ba_window_.fixed_point_distance_m = far_m(options_.full_ba.far_point_disparity_px);
}

MapperStep Mapper::add_keyframe(MapperKeyframe keyframe) {
  MapperStep step;
  const int64_t id = keyframe.id;
  MapCorrection c;
  c.map_id = keyframe.map_id;
  c.t_ns = keyframe.state.t_ns;
  resolve_aliases(keyframe);
  for (MapperKeypoint& kp : keyframe.keypoints) {
    if (kp.point_id < 0 || !removed_points_.count(kp.point_id)) continue;
    keyframe.point_positions.erase(kp.point_id);
    kp.point_id = -1;
    ++counters_.removed_point_observations;
  }
  if (graph_.insert(std::move(keyframe)) == KeyframeGraph::InsertResult::kDuplicate) {
    step.message = "keyframe " + std::to_string(id) + " seen before: ignored";
    return step;
  }
  ++counters_.keyframes;
  // A full BA that finished meets the graph before this keyframe's local BA builds on it.
  bool whole_world = apply_finished_full_ba(!options_.full_ba.background, step);
  const int every = options_.inertial.every_keyframes;
  if (every > 0 && counters_.keyframes % every == 0) refine_inertial(id, step);

  if (!options_.localisation_only) {
    const std::vector<NewPoint> made =
        triangulate_new_points(graph_, id, calib_, options_.new_points);
    for (const NewPoint& p : made) graph_.add_point(p.p_w, {p.a, p.b});
    step.new_points = static_cast<int>(made.size());
    counters_.new_points += step.new_points;
  }
  if (options_.fuse_revisits) fuse(id, revisited_points(id), step);
  LocalWindow window = graph_.local_window(id);
  if (options_.localisation_only) {
    // The loaded map holds still: its keyframes join the fixed set.
    const auto split = std::stable_partition(window.keyframes.begin(), window.keyframes.end(),
                                             [&](int64_t k) { return !frozen_keyframe(k); });
    window.fixed_keyframes.insert(window.fixed_keyframes.end(), split, window.keyframes.end());
    window.keyframes.erase(split, window.keyframes.end());
    std::sort(window.fixed_keyframes.begin(), window.fixed_keyframes.end());
  }
  WindowInput problem = window_input(graph_, window, options_.window);
  for (BaPoint& p : problem.input.points) p.fixed = p.fixed || frozen_point(p.id);
  // A mono window (no cam1 view in it) has its gravity from a rougher start than the levelling
  // at rest, and lets it move.
  const bool mono =
      std::none_of(problem.input.observations.begin(), problem.input.observations.end(),
                   [](const BaObservation& o) { return o.camera == 1; });
  problem.input.gravity = {
      g_w_, mono ? options_.window_gravity_mono_sigma_rad : options_.window_gravity_sigma_rad};
  counters_.imu_factors_skipped += problem.imu_factors_skipped;
  step.window_keyframes = static_cast<int>(window.keyframes.size());
  step.window_points = static_cast<int>(problem.input.points.size());
  step.window_observations = static_cast<int>(problem.input.observations.size());
  LocalBaResult result;
  try {
    result = ba_.optimise(problem.input);
  } catch (const std::invalid_argument& e) {
    // The graph only holds validated keyframes, so this is a bug, not bad input: say so and
    // send nothing rather than a correction built on it.
    step.message = std::string("local BA refused its window: ") + e.what();
    return step;
  }
  ++counters_.local_ba_runs;
  step.ba = result.stats;
  g_w_ = result.g_w;

  for (const BaKeyframe& k : result.keyframes) {
    if (k.fixed) continue;
    graph_.set_state(k.id, k.state);
    c.keyframes.push_back({k.id, k.state});
  }
  std::unordered_map<int64_t, std::pair<int, int>> tally;  // point -> (observations, outliers)
  for (size_t k = 0; k < problem.input.observations.size(); ++k) {
    auto& [seen, failed] = tally[problem.input.observations[k].point_id];
    ++seen;
    failed += result.outliers[k] ? 1 : 0;
  }
  for (const BaPoint& p : result.points) {
    const auto [seen, failed] = tally[p.id];
    if (!frozen_point(p.id) && failed >= 2 && failed >= options_.point_outlier_ratio * seen) {
      remove_point(p.id, c);
      continue;
    }
    graph_.set_position(p.id, p.p_w);
    add_point_correction(p.id, p.p_w, c);
  }

  if (options_.loop.enabled) detect_loop(id, step);
  bool world_moved = false;
  if (step.loop && step.loop->merge) {
    merge_worlds(step);
    world_moved = true;
  } else if (step.loop && !options_.localisation_only && options_.loop_closing.enabled) {
    world_moved = close_loop(step);
  }
  whole_world = whole_world || world_moved;
  if (step.loop && options_.fuse_revisits)
    fuse(id,
         neighbourhood_points(graph_, step.loop->candidate, options_.loop.neighbourhood_keyframes),
         step);
  if (whole_world) {
    c.keyframes.clear();
    c.points.clear();
    fill_world_correction(id, c);
  }
  if (options_.cull_keyframes) {
    for (int64_t k : redundant_keyframes(graph_, window.keyframes, options_.culling)) {
      if (const auto prev = graph_.imu_predecessor(k))
        culled_[k] = {*prev, graph_.keyframe(*prev)->state.T_w_b().inverse() *
                                 graph_.keyframe(k)->state.T_w_b()};
      graph_.remove_keyframe(k);
      loops_.remove(k);
      ++counters_.culled_keyframes;
    }
  }
  c.g_w = g_w_;
  c.seq = next_seq_++;
  step.correction = std::move(c);
  const int full_every = options_.full_ba.every_keyframes;
  if (world_moved || (full_every > 0 && counters_.keyframes % full_every == 0)) start_full_ba(id);
  return step;
}

void Mapper::start_full_ba(int64_t id) {
  if (!options_.full_ba.enabled || options_.localisation_only) return;
  if (full_ba_) {
    full_ba_->keyframe = id;
    full_ba_->stale = true;
    return;
  }
  RunningFullBa run;
  run.keyframe = id;
  run.input = full_ba_input(graph_, graph_.world(id), g_w_, full_ba_window_,
                            [this](int64_t k) { return frozen_keyframe(k); });
  // The thread works on its own copy: the snapshot stays to tell what moved since.
  run.result = std::async(std::launch::async, [solver = &full_ba_solver_, input = run.input] {
    return solver->optimise(input);
  });
  full_ba_ = std::move(run);
}

bool Mapper::apply_finished_full_ba(bool wait, MapperStep& step) {
  if (!full_ba_) return false;
  if (!wait && full_ba_->result.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
    return false;
  RunningFullBa run = std::move(*full_ba_);
  full_ba_.reset();
  LocalBaResult result;
  try {
    result = run.result.get();
  } catch (const std::invalid_argument& e) {
    add_message(step, std::string("full BA refused its input: ") + e.what());
    return false;
  }
  if (run.stale) {
    ++counters_.full_bas_discarded;
    if (graph_.keyframe(run.keyframe)) start_full_ba(run.keyframe);
    return false;
  }
  step.full_ba_applied = apply_full_ba(graph_, run.input, result);
  step.full_ba = result.stats;
  ++counters_.full_bas;
  add_message(step, "full BA applied: " + std::to_string(step.full_ba_applied.keyframes) +
                        " keyframes, " + std::to_string(step.full_ba_applied.points) + " points, " +
                        std::to_string(result.stats.iterations) + " iterations, " +
                        std::to_string(result.stats.time_ms) + " ms; " +
                        std::to_string(step.full_ba_applied.keyframes_moved) +
                        " keyframes added meanwhile moved with it");
  return true;
}

MapperStep Mapper::finish_full_ba(bool wait) {
  MapperStep step;
  if (!apply_finished_full_ba(wait, step) || graph_.num_keyframes() == 0) return step;
  const MapperKeyframe& newest = *graph_.keyframe(graph_.keyframe_ids().back());
  MapCorrection c;
  c.map_id = newest.map_id;
  c.t_ns = newest.state.t_ns;
  fill_world_correction(newest.id, c);
  c.g_w = g_w_;
  c.seq = next_seq_++;
  step.correction = std::move(c);
  return step;
}

RelocAnswer Mapper::relocalise(const MapperKeyframe& frame, int64_t seq, int32_t next_map_id) {
  ++counters_.reloc_requests;
  RelocAnswer a;
  a.seq = seq;
  a.t_ns = frame.state.t_ns;
  if (graph_.world_of_map(next_map_id)) {
    a.message = "map id " + std::to_string(next_map_id) + " is in use: cannot continue in it";
    return a;
  }
  LoopQueryStats st;
  const std::optional<PlaceFix> fix =
      loops_.relocalise(graph_, frame, graph_.world_of_map(frame.map_id), &st);
  if (!fix) {
    a.message = "not found in the atlas (" + std::to_string(st.candidates) + " candidates, " +
                std::to_string(st.verified) + " verified" +
                (st.message.empty() ? "" : ", last: " + st.message) + ")";
    return a;
  }
  graph_.join_map(next_map_id, graph_.world(fix->keyframe));
  ++counters_.relocalisations;
  a.found = true;
  a.map_id = next_map_id;
  a.keyframe_id = fix->keyframe;
  a.T_w_b = fix->T_w_b;
  a.inliers = fix->inliers;
  a.message = "found in the atlas: " + st.message + "; map id " + std::to_string(next_map_id) +
              " continues keyframe " + std::to_string(fix->keyframe) + "'s map";
  return a;
}

void Mapper::detect_loop(int64_t id, MapperStep& step) {
  LoopQueryStats stats;
  step.loop = loops_.detect(graph_, id, &stats, !options_.localisation_only);
  ++counters_.loop_queries;
  counters_.places_verified += stats.verified;
  counters_.places_implausible += stats.implausible;
  counters_.places_unconfirmed += stats.unconfirmed;
  if (step.loop) ++counters_.loops_detected;
  if (!stats.message.empty()) add_message(step, stats.message);
  step.loop_query = stats;
}

std::optional<Eigen::Isometry3d> Mapper::keyframe_pose(int64_t id) const {
  Eigen::Isometry3d T_prev_k = Eigen::Isometry3d::Identity();
  for (;;) {
    if (const MapperKeyframe* kf = graph_.keyframe(id)) return kf->state.T_w_b() * T_prev_k;
    const auto it = culled_.find(id);
    if (it == culled_.end()) return std::nullopt;
    T_prev_k = it->second.second * T_prev_k;
    id = it->second.first;
  }
}

bool Mapper::close_loop(MapperStep& step) {
  const LoopFound& loop = *step.loop;
  const LoopClosingOptions& o = options_.loop_closing;
  if (keyframes_at_last_closure_ >= 0 &&
      counters_.keyframes - keyframes_at_last_closure_ < o.min_keyframes_between)
    return false;
  if (loop.drift.translation().norm() < o.min_correction_m &&
      Eigen::AngleAxisd(loop.drift.linear()).angle() < o.min_correction_rad)
    return false;
  closed_loops_.push_back(loop);
  closed_worlds_.insert(graph_.world(loop.query));
  step.closure = hs::close_loop(graph_, closed_loops_, o);
  keyframes_at_last_closure_ = counters_.keyframes;
  ++counters_.loops_closed;
  add_message(step, "loop closed: " + std::to_string(step.closure->keyframes) +
                        " keyframes, largest move " + std::to_string(step.closure->max_shift_m) +
                        " m, pose graph " + std::to_string(step.closure->graph.time_ms) + " ms");
  return true;
}

void Mapper::fill_world_correction(int64_t id, MapCorrection& c) const {
  const int32_t world = graph_.world(id);
  std::vector<int64_t> ids;  // the tracker's keyframes: not a loaded map's
  for (int64_t k : graph_.keyframe_ids())
    if (graph_.world(k) == world && !loaded_keyframe(k)) ids.push_back(k);
  std::unordered_set<int64_t> points;
  for (size_t n = 0; n < ids.size(); ++n) {
    const MapperKeyframe& kf = *graph_.keyframe(ids[n]);
    c.keyframes.push_back({kf.id, kf.state});
    if (n + options_.loop_correction_point_keyframes < ids.size()) continue;
    for (const MapperKeypoint& kp : kf.keypoints) {
      const MapperPoint* p = kp.point_id >= 0 ? graph_.point(kp.point_id) : nullptr;
      if (p && points.insert(p->id).second) add_point_correction(p->id, p->p_w, c);
    }
  }
}

void Mapper::merge_worlds(MapperStep& step) {
  const LoopFound& loop = *step.loop;
  const int32_t from = graph_.world(loop.query);
  const int32_t into = graph_.world(loop.candidate);
  const Eigen::Isometry3d& T = loop.drift;  // `from`'s frame -> `into`'s
  for (int64_t k : graph_.keyframe_ids())
    if (graph_.world(k) == from) graph_.set_state(k, transformed(graph_.keyframe(k)->state, T));
  for (int64_t id : graph_.point_ids()) {
    const MapperPoint& p = *graph_.point(id);
    if (graph_.world(p.observations.front().keyframe_id) == from)
      graph_.set_position(id, T * p.p_w);
  }
  graph_.merge_world(from, into);
  if (closed_worlds_.erase(from)) closed_worlds_.insert(into);
  g_w_ = T.linear() * g_w_;
  closed_loops_.push_back(loop);  // an edge of later pose graphs
  ++counters_.maps_merged;
  step.merged = true;
  add_message(step, "map merged: keyframe " + std::to_string(loop.query) + "'s world moved " +
                        std::to_string(T.translation().norm()) + " m onto keyframe " +
                        std::to_string(loop.candidate) + "'s");
}

std::vector<int64_t> Mapper::revisited_points(int64_t id) const {
  const MapperKeyframe& kf = *graph_.keyframe(id);
  const auto min_age_ns = static_cast<int64_t>(options_.loop.min_age_s * 1e9);
  // The new keyframe's own neighbourhood is mostly the current pass (it shares most points with
  // it): the old pass is reached through the old keyframes it already shares a few with.
  std::set<int64_t> points;
  size_t old = 0;
  for (int64_t k : graph_.most_covisible(id, graph_.num_keyframes())) {
    if (!loaded_keyframe(k) && kf.state.t_ns - graph_.keyframe(k)->state.t_ns < min_age_ns)
      continue;
    for (int64_t p : neighbourhood_points(graph_, k, options_.fusion.neighbourhood_keyframes))
      points.insert(p);
    if (++old == options_.fusion.revisited_keyframes) break;
  }
  return {points.begin(), points.end()};
}

void Mapper::fuse(int64_t id, const std::vector<int64_t>& points, MapperStep& step) {
  const bool ties = ties_across_a_loop(id);
  const FusionResult r = fuse_points_into(
      graph_, id, points, calib_, options_.fusion,
      [this](int64_t p) { return loaded_points_.count(p) > 0; }, ties);
  step.fused_points += r.fused;
  counters_.points_fused += r.fused;
  if (ties) counters_.points_fused_as_ties += r.fused;
  counters_.fusion_observations += r.observations_added;
  for (const auto& [drop, keep] : r.merged) {
    std::vector<int64_t>& to = alias_sources_[keep];
    if (auto moved = alias_sources_.extract(drop); !moved.empty())
      for (int64_t source : moved.mapped()) {
        aliases_[source] = keep;
        to.push_back(source);
      }
    if (tracker_point(drop)) {
      aliases_[drop] = keep;
      to.push_back(drop);
    }
  }
}

void Mapper::resolve_aliases(MapperKeyframe& keyframe) {
  std::unordered_set<int64_t> seen;
  for (MapperKeypoint& kp : keyframe.keypoints) {
    if (kp.point_id < 0) continue;
    if (const auto a = aliases_.find(kp.point_id); a != aliases_.end()) {
      if (const MapperPoint* kept = graph_.point(a->second)) {
        keyframe.point_positions.erase(kp.point_id);
        kp.point_id = a->second;
        if (ties_across_a_loop(kept->observations.front().keyframe_id)) kp.detected = true;
      } else {  // the kept point is gone since: the tracker's stands alone again
        aliases_.erase(a);
      }
    }
    // Two of the tracker's points fused into one: the keyframe sees it once.
    if (!seen.insert(kp.point_id).second) kp.point_id = -1;
  }
}

void Mapper::add_point_correction(int64_t id, const Eigen::Vector3d& p_w, MapCorrection& c) const {
  if (tracker_point(id)) c.points.push_back({id, p_w});
  if (const auto s = alias_sources_.find(id); s != alias_sources_.end())
    for (int64_t source : s->second) c.points.push_back({source, p_w});
}

void Mapper::remove_point(int64_t id, MapCorrection& c) {
  graph_.remove_point(id);
  ++counters_.removed_points;
  std::vector<int64_t> ids{id};
  if (auto s = alias_sources_.extract(id); !s.empty()) {
    for (int64_t source : s.mapped()) aliases_.erase(source);
    ids.insert(ids.end(), s.mapped().begin(), s.mapped().end());
  }
  for (int64_t removed : ids) {
    removed_points_.insert(removed);
    if (tracker_point(removed)) c.removed_points.push_back(removed);
  }
}

void Mapper::refine_inertial(int64_t newest, MapperStep& step) {
  int skipped = 0;  // counted by the local BA's window too: not counted twice
  const LocalBaInput input = inertial_refinement_input(
      graph_, newest, default_gravity_w(), options_.inertial, options_.window, &skipped);
  if (input.keyframes.empty()) return;
  LocalBaResult result;
  try {
    result = ba_.optimise(input);
  } catch (const std::invalid_argument& e) {
    add_message(step, std::string("IMU refinement refused its input: ") + e.what());
    return;
  }
  step.inertial = result.stats;
  if (const double tilt = gravity_tilt_rad(result.g_w); !(tilt <= options_.inertial.max_tilt_rad)) {
    ++counters_.inertial_refinements_rejected;
    add_message(step, "IMU refinement over " + std::to_string(input.keyframes.size()) +
                          " keyframes not adopted: gravity " + std::to_string(tilt * 180.0 / M_PI) +
                          " deg off -z");
    return;
  }
  ++counters_.inertial_refinements;
  g_w_ = result.g_w;
  for (const BaKeyframe& k : result.keyframes) graph_.set_state(k.id, k.state);
}

}  // namespace hs
