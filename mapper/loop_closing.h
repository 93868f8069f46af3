#pragma once
// Loop correction (issue 7): a detected loop that implies a correction worth making runs a
// pose-graph optimisation over the essential graph of the loop's world (each keyframe linked to
// the previous one and to those it shares many points with, at their relative poses before the
// loop, plus every loop closed so far, as measured), with the world's oldest keyframe held.
// The keyframes take the optimised poses (velocities turned with them) and each point moves
// with the first keyframe that observed it.
#include <cstdint>
#include <vector>

#include "mapper/keyframe_graph.h"
#include "mapper/loop_detector.h"
#include "mapper/pose_graph.h"

namespace hs {

struct LoopClosingOptions {
  bool enabled = true;
  // A loop implying less than this is confirmed, not closed: the map already agrees, and a
  // verified relative pose is good to 1-2 cm only (closing at 2 cm: vehicle_loop final ATE
  // 1.85 cm instead of 2.2 cm, but room_mav 0.57 cm instead of 0.29 cm, its drift being smaller
  // than the loop's error).
  double min_correction_m = 0.05;
  double min_correction_rad = 0.5 * M_PI / 180.0;
  int min_keyframes_between = 10;  // keyframes since the last closure
  int strong_covisibility = 100;   // shared points for an essential-graph edge
  double loop_weight = 1.0;        // information of a loop edge relative to an odometry edge
  PoseGraphOptions pose_graph;
};

struct LoopClosureStats {
  int keyframes = 0;  // in the pose graph
  int edges = 0;
  int points_moved = 0;
  double max_shift_m = 0.0;  // largest keyframe move
  PoseGraphResult graph;     // without the poses
};

// Closes `loops.back()` (all of `loops` join the graph): returns what was done.
LoopClosureStats close_loop(KeyframeGraph& graph, const std::vector<LoopFound>& loops,
                            const LoopClosingOptions& options);

}  // namespace hs
