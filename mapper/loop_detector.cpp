#include "mapper/loop_detector.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <unordered_set>

#include "mapper/point_fusion.h"

namespace hs {
namespace {

double rotation_rad(const Eigen::Isometry3d& T) {
  return Eigen::AngleAxisd(T.linear()).angle();
}

// How far a rotation turns the vertical: its roll/pitch part.
double tilt_rad(const Eigen::Matrix3d& R) {
  return std::acos(std::clamp((R * Eigen::Vector3d::UnitZ()).z(), -1.0, 1.0));
}

}  // namespace

LoopDetector::LoopDetector(const StereoCalib& calib, const LoopDetectionOptions& options)
    : calib_(calib), options_(options), index_(options.index) {}

double LoopDetector::path_at(const KeyframeGraph& graph, int64_t id) {
  if (const auto it = path_m_.find(id); it != path_m_.end()) return it->second;
  const Eigen::Vector3d& p = graph.keyframe(id)->state.p_w_b;
  WorldPath& w = world_path_[graph.world(id)];
  if (w.last) w.length_m += (p - *w.last).norm();
  w.last = p;
  return path_m_[id] = w.length_m;
}

double LoopDetector::neighbourhood_share(const KeyframeGraph& graph, const MapperKeyframe& query,
                                         const MapperKeyframe& candidate,
                                         const Eigen::Isometry3d& T_c_q, int* projected) const {
  PointFusionOptions match;
  match.max_hamming = options_.verify.max_hamming;
  match.ratio = options_.verify.ratio;
  match.radius_px = options_.neighbourhood_radius_px;
  match.max_depth_error = 0.0;
  const std::vector<ProjectedMatch> found = match_projected_points(
      graph, query, candidate.state.T_w_b() * T_c_q,
      neighbourhood_points(graph, candidate.id, options_.neighbourhood_keyframes), calib_, match,
      projected);
  return *projected > 0 ? static_cast<double>(found.size()) / *projected : 0.0;
}

bool LoopDetector::neighbourhood_agrees(const KeyframeGraph& graph, const MapperKeyframe& query,
                                        const MapperKeyframe& candidate,
                                        const Eigen::Isometry3d& T_c_q, LoopQueryStats& st) const {
  int projected = 0;
  const double share = neighbourhood_share(graph, query, candidate, T_c_q, &projected);
  st.message += "; its neighbourhood: " + std::to_string(static_cast<int>(share * 100)) + "% of " +
                std::to_string(projected) + " points found";
  if (share >= options_.min_neighbourhood_share) return true;
  ++st.unconfirmed;
  return false;
}

std::optional<LoopFound> LoopDetector::detect(const KeyframeGraph& graph, int64_t query,
                                              LoopQueryStats* stats, bool join_index) {
  LoopQueryStats local;
  LoopQueryStats& st = stats ? *stats : local;
  st = {};
  const auto start = std::chrono::steady_clock::now();
  const MapperKeyframe& q = *graph.keyframe(query);
  const double path_q = path_at(graph, query);
  const int32_t world = graph.world(query);
  const int64_t min_age_ns = static_cast<int64_t>(options_.min_age_s * 1e9);
  // Another world's keyframes and a loaded map's have no age relative to the query.
  const auto exclude = [&](int64_t id) {
    const MapperKeyframe* c = graph.keyframe(id);
    if (!c) return true;
    if (graph.world(id) != world) return !options_.merge_worlds;
    return (!foreign_.count(id) && q.state.t_ns - c->state.t_ns < min_age_ns) ||
           graph.shared_points(query, id) > 0;
  };
  const std::vector<PlaceCandidate> candidates =
      index_.query(q.descriptors, options_.candidates, exclude);
  if (join_index) index_.add(query, q.descriptors);
  st.candidates = static_cast<int>(candidates.size());

  std::optional<LoopFound> found;
  for (const PlaceCandidate& pc : candidates) {
    const MapperKeyframe& c = *graph.keyframe(pc.keyframe_id);
    const PlaceMatch m = verify_place(q, c, calib_, options_.verify);
    if (!m.ok) continue;
    ++st.verified;
    LoopFound loop{query,   c.id, q.state.t_ns, c.state.t_ns,
                   m.T_c_q, {},   m.inliers,    path_q - path_at(graph, c.id)};
    loop.drift = c.state.T_w_b() * m.T_c_q * q.state.T_w_b().inverse();
    loop.merge = graph.world(c.id) != world;
    // The drift since the candidate is bounded along one run of one world; a world of this run
    // was started in place (merge_in_run_*); a loaded map's frame is anywhere.
    const bool loaded = foreign_.count(c.id) > 0;
    const double drift_m = (loop.drift * q.state.p_w_b - q.state.p_w_b).norm();
    // A merge of a world started in place after a loss: bounded by the loss's IMU drift.
    const bool in_run_merge = loop.merge && !loaded;
    const double max_m = in_run_merge ? options_.merge_in_run_m
                                      : options_.drift_base_m + options_.drift_per_m * loop.path_m;
    const double max_rad = in_run_merge
                               ? options_.merge_in_run_rad
                               : options_.drift_base_rad + options_.drift_rad_per_m * loop.path_m;
    char why[200];
    std::snprintf(why, sizeof(why),
                  "keyframe %ld matches keyframe %ld (%d inliers) with a correction of %.2f m "
                  "(allowed %.2f), %.2f deg (allowed %.2f), tilt %.2f deg after %.1f m",
                  static_cast<long>(query), static_cast<long>(c.id), m.inliers, drift_m, max_m,
                  rotation_rad(loop.drift) * 180 / M_PI, max_rad * 180 / M_PI,
                  tilt_rad(loop.drift.linear()) * 180 / M_PI, loop.path_m);
    st.message = why;
    if ((!loaded && (drift_m > max_m || rotation_rad(loop.drift) > max_rad)) ||
        tilt_rad(loop.drift.linear()) > options_.max_tilt_rad) {
      ++st.implausible;
      continue;
    }
    if (!neighbourhood_agrees(graph, q, c, m.T_c_q, st)) continue;
    found = loop;
    break;
  }
  // The streak continues when this keyframe's loop implies the same world correction.
  if (found && streak_) {
    const Eigen::Isometry3d change = streak_->drift.inverse() * found->drift;
    const bool agrees = change.translation().norm() <= options_.consistency_m &&
                        rotation_rad(change) <= options_.consistency_rad;
    streak_length_ = agrees ? streak_length_ + 1 : 1;
  } else {
    streak_length_ = found ? 1 : 0;
  }
  streak_ = found;
  st.time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (!found || streak_length_ < options_.consistent) return std::nullopt;
  st.message = "loop: " + st.message;
  return found;
}

std::optional<PlaceFix> LoopDetector::relocalise(const KeyframeGraph& graph,
                                                 const MapperKeyframe& frame,
                                                 std::optional<int32_t> guess_world,
                                                 LoopQueryStats* stats) const {
  LoopQueryStats local;
  LoopQueryStats& st = stats ? *stats : local;
  st = {};
  const auto start = std::chrono::steady_clock::now();
  const std::vector<PlaceCandidate> candidates = index_.query(
      frame.descriptors, options_.candidates, [&](int64_t id) { return !graph.keyframe(id); });
  st.candidates = static_cast<int>(candidates.size());
  std::optional<PlaceFix> fix;
  for (const PlaceCandidate& pc : candidates) {
    const MapperKeyframe& c = *graph.keyframe(pc.keyframe_id);
    const PlaceMatch m = verify_place(frame, c, calib_, options_.verify);
    if (!m.ok) continue;
    ++st.verified;
    const Eigen::Isometry3d T_w_b = c.state.T_w_b() * m.T_c_q;
    const Eigen::Isometry3d jump = T_w_b * frame.state.T_w_b().inverse();
    const bool bounded = guess_world && graph.world(c.id) == *guess_world;
    const double jump_m = (T_w_b.translation() - frame.state.p_w_b).norm();
    char why[200];
    std::snprintf(why, sizeof(why),
                  "keyframe %ld (%d inliers) places the frame %.2f m / %.2f deg from the "
                  "tracker's guess%s, tilt %.2f deg",
                  static_cast<long>(c.id), m.inliers, jump_m, rotation_rad(jump) * 180 / M_PI,
                  bounded ? "" : " (another map: not bounded)",
                  tilt_rad(jump.linear()) * 180 / M_PI);
    st.message = why;
    if ((bounded &&
         (jump_m > options_.merge_in_run_m || rotation_rad(jump) > options_.merge_in_run_rad)) ||
        tilt_rad(jump.linear()) > options_.max_tilt_rad) {
      ++st.implausible;
      continue;
    }
    if (!neighbourhood_agrees(graph, frame, c, m.T_c_q, st)) continue;
    fix = PlaceFix{c.id, T_w_b, m.inliers};
    break;
  }
  st.time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return fix;
}

}  // namespace hs
