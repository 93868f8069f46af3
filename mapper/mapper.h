#pragma once
// The back end's local mapping (paper Fig. 4, as ORB-SLAM3's local mapping): each keyframe from
// the tracker joins the keyframe graph, a local visual-inertial bundle adjustment runs over its
// covisible window, points that fail it are removed, redundant keyframes are culled, and the
// refined window goes back to the tracker as a MapCorrection. Single-threaded and
// deterministic; the hs-mapper process and hs-run --with-mapper drive it.
#include <cmath>
#include <cstdint>
#include <future>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "common/calib/camera_calib.h"
#include "common/core/map_correction.h"
#include "common/core/reloc_answer.h"
#include "mapper/full_ba.h"
#include "mapper/inertial_refinement.h"
#include "mapper/keyframe_culling.h"
#include "mapper/keyframe_graph.h"
#include "mapper/local_ba.h"
#include "mapper/loop_closing.h"
#include "mapper/loop_detector.h"
#include "mapper/map_file.h"
#include "mapper/new_points.h"
#include "mapper/point_fusion.h"
#include "mapper/window_input.h"

namespace hs {

struct MapperOptions {
  KeyframeGraphOptions graph;
  WindowInputOptions window;
  LocalBaOptions ba;
  NewPointOptions new_points;
  CullingOptions culling;
  bool cull_keyframes = true;
  // Gravity direction, velocities and biases over a long chain stretch.
  InertialRefinementOptions inertial;
  LoopDetectionOptions loop;
  LoopClosingOptions loop_closing;
  FullBaOptions full_ba;  // after a loop closure or a merge
  // Points of a revisited place found again in the new keyframe are fused with it (after a
  // loop or merge, and for every keyframe covisible with one at least loop.min_age_s older or
  // loaded): the two passes then share points and every local BA holds them together.
  bool fuse_revisits = true;
  PointFusionOptions fusion;
  // Localisation only (with a loaded map): the loaded keyframes and points are held fixed, the
  // new keyframes do not join the place index or the saved map, and the mapper triangulates no
  // points and closes no loops; a match with the loaded map merges the tracker's world into it.
  bool localisation_only = false;
  // After a loop closure the correction carries every keyframe of the world and the points of
  // this many newest keyframes (those the tracker can still hold).
  size_t loop_correction_point_keyframes = 20;
  // Each local BA may turn gravity this far (prior sigma) from the current estimate and its
  // result carries on; the inertial refinement re-anchors it. 0 holds it for the BA. Measured
  // (ATE, tracker alone 0.40 cm on room_mav 20 s, 6.6 cm on vehicle_loop): 0 deg 0.35 / 7.4 cm,
  // 0.1 deg 0.23 / 9.1 cm, 0.25 deg 0.20 / 12.1 cm; not carried on (window only) 0.24 / 12.0 cm.
  // With the front end's slanted stereo and pixel_sigma 0.15 (vehicle_loop 50 s seeds 1-4, tracker
  // alone 3.98 cm mean): 0.1 deg 2.21 / 2.74 / 8.32 / 2.89 cm, 0 deg 1.95 / 3.15 / 4.22 / 3.26 cm:
  // a gravity that walks a little with every BA tilts the straights after the start.
  double window_gravity_sigma_rad = 0.0;
  // The same for a mono window (no cam1 observation): its gravity comes from the tracker's
  // visual-inertial alignment. room_mav 40 s from cam0 with the mapper: ATE 2.7 cm at 0.1 deg,
  // 11 cm at 0.
  double window_gravity_mono_sigma_rad = 0.1 * M_PI / 180.0;

  // A point is removed when at least this share of its observations in the window (and at
  // least two) fail the bundle adjustment's chi2 test.
  double point_outlier_ratio = 0.5;
  // Points whose stereo disparity would be under this from every optimised keyframe (farther
  // than fx * baseline / this: 8.4 m for EuRoC's rig) are held where they are. A short window
  // moving towards them constrains their depth less than their own stereo match did, and left
  // free they let the window slide. ATE with / without the mapper, vehicle_loop 50 s (mean of
  // seeds 1, 3, 4) and room_mav 20 s: free 2.30x and 0.57x; 12.6 px (4 m) 0.98x; 10 px (5 m)
  // 1.05x and 0.68x; 6 px 0.91x and 0.36x; 5 px (10 m) 1.06x and 0.36x. 0: none held.
  double far_point_disparity_px = 6.0;
};

// Cumulative.
struct MapperCounters {
  int64_t keyframes = 0;  // accepted into the graph
  int64_t local_ba_runs = 0;
  int64_t inertial_refinements = 0;           // adopted
  int64_t inertial_refinements_rejected = 0;  // implausible result: not adopted
  int64_t new_points = 0;                     // triangulated by the mapper
  int64_t culled_keyframes = 0;
  int64_t removed_points = 0;
  // Keypoints of later keyframes still naming a removed point (sent before the tracker applied
  // the removal): the association is dropped, the point stays removed.
  int64_t removed_point_observations = 0;
  int64_t imu_factors_skipped = 0;  // keyframe intervals with an IMU gap
  int64_t loop_queries = 0;
  int64_t places_verified = 0;     // candidates that passed geometric verification
  int64_t places_implausible = 0;  // ... but implied an implausible drift: not loops
  int64_t places_unconfirmed = 0;  // ... or the candidate's neighbourhood disagreed
  int64_t loops_detected = 0;
  int64_t loops_closed = 0;          // pose graph run, map corrected
  int64_t maps_merged = 0;           // a world moved onto another it was found in
  int64_t full_bas = 0;              // applied
  int64_t full_bas_discarded = 0;    // a loop or merge came while it ran: started again
  int64_t points_fused = 0;          // points found to be another, merged
  int64_t points_fused_as_ties = 0;  // ... in a world a loop was closed in (ties_across_a_loop)
  int64_t fusion_observations = 0;   // free keypoints that found a map point
  int64_t reloc_requests = 0;        // a lost tracker asked where it is
  int64_t relocalisations = 0;       // ... and was placed in the atlas
};

struct MapperStep {
  std::optional<MapCorrection> correction;  // none for a duplicate keyframe
  LocalBaStats ba;
  std::optional<LocalBaStats> inertial;  // when the inertial refinement ran before the BA
  int new_points = 0;                    // triangulated for this keyframe
  int window_keyframes = 0;
  int window_points = 0;                     // in the BA: seen by two keyframes or more
  int window_observations = 0;               // reprojection terms
  std::optional<LoopQueryStats> loop_query;  // when loop detection ran
  std::optional<LoopFound> loop;
  std::optional<LoopClosureStats> closure;  // when the loop was closed
  bool merged = false;                      // the loop merged the query's world into another
  std::optional<LocalBaStats> full_ba;      // when a full BA's result was applied
  FullBaApplied full_ba_applied;
  int fused_points = 0;
  std::string message;  // what was dropped and why, if anything
};

class Mapper {
 public:
  Mapper(const StereoCalib& calib, const MapperOptions& options);

  MapperStep add_keyframe(MapperKeyframe keyframe);
  // A lost tracker's frame (its keypoints, stereo points and IMU-carried guess in map
  // frame.map_id): where the atlas places it (LoopDetector::relocalise). When found, map id
  // `next_map_id` joins the matched keyframe's world, so the keyframes the tracker then sends
  // in it continue that world. The frame does not join the graph or the index.
  RelocAnswer relocalise(const MapperKeyframe& frame, int64_t seq, int32_t next_map_id);
  // A full BA running in the background (see FullBaOptions)?
  bool full_ba_running() const { return full_ba_.has_value(); }
  // Applies a full BA that has finished (or waits for it when `wait`) and returns the world's
  // correction, between keyframes: e.g. when the vehicle stands still, or at the end of a run.
  MapperStep finish_full_ba(bool wait);

  // The map as it is now (mapper_map_file.cpp), and a mapper started from one: its keyframes,
  // points, closed loops and gravity, as a world of its own (ids moved out of the way of the
  // tracker's, which start from 0 again). Only on a fresh mapper.
  MapFile map_file() const;
  void load(const MapFile& map);

  const KeyframeGraph& graph() const { return graph_; }
  const MapperCounters& counters() const { return counters_; }
  // Gravity in the tracker's world frame as estimated so far.
  const Eigen::Vector3d& gravity_w() const { return g_w_; }
  size_t loop_index_bytes() const { return loops_.index().memory_bytes(); }
  // A keyframe's pose as the mapper has it now; a culled one's through the keyframe it was
  // relative to when culled. None for keyframes it never had.
  std::optional<Eigen::Isometry3d> keyframe_pose(int64_t id) const;

 private:
  void refine_inertial(int64_t newest, MapperStep& step);
  void detect_loop(int64_t id, MapperStep& step);
  // Starts a full BA of `id`'s world; one already running is discarded when it ends.
  void start_full_ba(int64_t id);
  // Applies a finished full BA to the graph (or waits for it); true when it did.
  bool apply_finished_full_ba(bool wait, MapperStep& step);
  // Runs the pose graph for step.loop if its correction is worth it; true when it did.
  bool close_loop(MapperStep& step);
  // Every keyframe of `id`'s world and the points of its newest keyframes, as they are now.
  void fill_world_correction(int64_t id, MapCorrection& c) const;
  // step.loop is with another world: the query's world moves onto it and joins it.
  void merge_worlds(MapperStep& step);
  // Fuses `points` into keyframe `id` and remembers the merged points the tracker names.
  void fuse(int64_t id, const std::vector<int64_t>& points, MapperStep& step);
  // The points around the old keyframes (loop.min_age_s older, or loaded) that keyframe `id`
  // shares points with: a place visited before. None if it shares none.
  std::vector<int64_t> revisited_points(int64_t id) const;
  // Tracker point ids the keyframe names for points since fused into others: the kept ones.
  void resolve_aliases(MapperKeyframe& keyframe);
  // Whether a fused point's observations along the dropped track weigh as detections in keyframe
  // `id`'s world: yes once a loop was closed in it. The track is off the kept point's by the two
  // detections' difference (about a pixel), a bias no chain of tracked (0.15 px) observations
  // averages away: at the tracked weight the tie fails chi2 and the second lap loses its hold on
  // the first (vehicle_loop). In a world no loop was closed in, the passes already agree better
  // than that and a rejected tie costs nothing (room_mav 20 s: 0.88 mm with the mapper either
  // way here, 1.26 mm when every fused track weighs as detections).
  bool ties_across_a_loop(int64_t id) const { return closed_worlds_.count(graph_.world(id)) > 0; }
  // A point's position for the tracker: under its id if the tracker has it, and under every
  // id of the tracker's fused into it.
  void add_point_correction(int64_t id, const Eigen::Vector3d& p_w, MapCorrection& c) const;
  void remove_point(int64_t id, MapCorrection& c);
  bool tracker_point(int64_t id) const { return !mapper_made_point(id) && id < kLoadedPointIdBase; }
  bool frozen_keyframe(int64_t id) const {
    return options_.localisation_only && loaded_keyframe(id);
  }
  bool frozen_point(int64_t id) const {
    return options_.localisation_only && loaded_points_.count(id);
  }

  MapperOptions options_;
  StereoCalib calib_;
  KeyframeGraph graph_;
  LocalBundleAdjuster ba_;
  LocalBundleAdjuster full_ba_solver_;
  WindowInputOptions full_ba_window_;  // the window's, with the full BA's far-point distance
  struct RunningFullBa {
    int64_t keyframe = -1;  // started after this keyframe's loop or merge
    LocalBaInput input;     // the snapshot
    std::future<LocalBaResult> result;
    bool stale = false;  // a loop or merge moved the world since: run again when it ends
  };
  std::optional<RunningFullBa> full_ba_;
  LoopDetector loops_;
  MapperCounters counters_;
  Eigen::Vector3d g_w_ = default_gravity_w();
  std::unordered_set<int64_t> removed_points_;
  std::unordered_set<int64_t> loaded_points_;
  Eigen::Vector3d loaded_g_w_ = Eigen::Vector3d::Zero();
  // Fused points: the dropped id -> the kept one, and the kept -> the tracker's ids fused into it.
  std::unordered_map<int64_t, int64_t> aliases_;
  std::unordered_map<int64_t, std::vector<int64_t>> alias_sources_;
  std::vector<LoopFound> closed_loops_;
  // Worlds a pose graph closed a loop in this run: their passes disagreed by more than a
  // detection's error, and fusion's ties hold them together (see ties_across_a_loop).
  std::unordered_set<int32_t> closed_worlds_;
  // Culled keyframe -> (its IMU predecessor then, its pose relative to it).
  std::unordered_map<int64_t, std::pair<int64_t, Eigen::Isometry3d>> culled_;
  int64_t keyframes_at_last_closure_ = -1;
  int64_t next_seq_ = 0;
};

}  // namespace hs
