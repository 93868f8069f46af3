#pragma once
// The mapper as the in-process back end of an offline run (hs-run --with-mapper), and what it
// did: local BA time per keyframe, window sizes, how far its corrections moved the pose.
#include <string>
#include <vector>

#include "mapper/mapper.h"
#include "tracker/offline/offline_run.h"

namespace hs {

struct MapperRunStats {
  std::vector<double> ba_ms;        // wall time per local BA
  std::vector<double> ba_cpu_ms;    // its thread CPU time
  std::vector<double> inertial_ms;  // per inertial refinement
  std::vector<double> window_keyframes, window_points, window_observations, ba_iterations;
  std::vector<double> loop_query_ms;  // place index query + verification, per keyframe
  std::vector<double> pose_graph_ms;  // per loop closed
  std::vector<double> full_ba_ms;     // per full BA applied (wall time in its thread)
  std::vector<double> full_ba_keyframes, full_ba_points;
  std::vector<double> full_ba_moved;  // keyframes that arrived while it ran, moved with it
  std::vector<LoopFound> loops;
  void add(const MapperStep& step);
};

// The options for a run that gives the same result every time: every bundle adjustment runs to
// its iteration limit however long it takes, and a full BA's result lands at the keyframe after
// its loop (it still runs in its own thread meanwhile).
MapperOptions reproducible(MapperOptions options);

// Feeds each KEYFRAME message to `mapper` (decoded and validated as hs-mapper would) and returns
// its correction; both must outlive the back end. Mapper messages go to stderr when verbose.
BackEnd in_process_back_end(Mapper& mapper, MapperRunStats& stats, bool verbose = false);
// Answers each RELOC_REQUEST message from `mapper`'s atlas (decoded as hs-mapper would).
AtlasBackEnd in_process_atlas(Mapper& mapper);

// At the end of a run: applies the full BA still running, if one is (its correction reaches
// no tracker: the final trajectory is on the mapper's keyframe poses).
void finish_back_end(Mapper& mapper, MapperRunStats& stats);

// One line per detected loop: keyframe times, the measured T_c_q (x y z qx qy qz qw), inliers,
// path since the candidate and the correction it implied.
void write_loops_csv(const std::string& path, const MapperRunStats& stats);

// The frames on the mapper's final keyframe poses (after loop closure): written as
// trajectory_final.tum and evaluated against the ground truth when there is one.
std::string final_trajectory_text(const std::string& out_dir, const OfflineRunResult& result,
                                  const Mapper& mapper);

std::string mapper_text(const MapperRunStats& stats, const Mapper& mapper,
                        const OfflineRunResult& result);

}  // namespace hs
