#pragma once
// Full bundle adjustment (paper Fig. 4, as ORB-SLAM3's global BA after a loop): every keyframe
// and point of one world, with the IMU chain, after a loop closure or a map merge has bent the
// world by a pose graph. It runs on a snapshot of the graph in a thread of its own while local
// mapping goes on; its result then meets a graph that has moved on (new keyframes and points,
// local BAs), so each keyframe and point takes it as a correction (see apply_full_ba).
#include <Eigen/Core>
#include <cstdint>
#include <functional>

#include "mapper/keyframe_graph.h"
#include "mapper/local_ba.h"
#include "mapper/window_input.h"

namespace hs {

struct FullBaOptions {
  // After each closure or merge. On the simulated drives it neither gains nor loses:
  // vehicle_loop 102 s seeds 1-10, final ATE with loops closed over without, ratio of sums
  // 0.296x with it, 0.295x without (the second lap localised in the first lap's saved map 1.47
  // cm with it, 1.42 cm without); it is there for the maps whose closure leaves more to settle.
  bool enabled = true;
  // In a thread of its own, applied at the first keyframe after it finished. false: the next
  // keyframe waits for it, so the result lands at the same keyframe on every run (hs-run's
  // in-process back end, tests).
  bool background = true;
  // Also every this many keyframes without a loop (0: after loops and merges only). The window
  // drifts where the whole lap would not: vehicle_loop 50 s, seeds 1-4, final ATE over the
  // tracker alone's 0.40/0.96/1.49/1.48x with the window only, 0.72/1.08/0.81/0.59x with 50 and
  // far_point_disparity_px 0 (far points held: seed 2 1.12x, seed 4 1.45x; each full BA 2.9 s over
  // 175 keyframes here). Off by default: it costs a core for seconds and loses on two seeds of
  // four.
  int every_keyframes = 0;
  int iterations_per_round = 10;  // two rounds: the second without the first's chi2 outliers
  // Points whose stereo disparity would be under this from every keyframe seeing them are held
  // at their position (4 m for EuRoC's rig), as the local BA's far points: left free, the BA
  // bends the map around their depth errors. vehicle_loop first lap (53 s), final ATE 1.44 cm
  // without the full BA: points held beyond 4 m 1.44 cm, beyond 8.4 m 1.47 cm, none 1.97 cm
  // (102 s); without its IMU factors 1.47 cm.
  double far_point_disparity_px = 12.6;
  double time_budget_ms = 60000.0;
};

// The problem over every keyframe of `world` (the oldest holds the gauge) and every point two
// of them see, gravity held. A point farther than options.fixed_point_distance_m from every
// keyframe seeing it is held; keyframes `frozen` names (a loaded map in localisation-only
// mode) too.
LocalBaInput full_ba_input(const KeyframeGraph& graph, int32_t world, const Eigen::Vector3d& g_w,
                           WindowInputOptions options,
                           const std::function<bool(int64_t)>& frozen = nullptr);

struct FullBaApplied {
  int keyframes = 0;        // optimised, still in the graph
  int keyframes_moved = 0;  // added since the snapshot: moved with the newest optimised one
  int points = 0;
  int points_moved = 0;  // added since, moved with the keyframe that first saw them
};

// Applies `result` of `input` (a snapshot of `graph`) to the graph as it is now. A keyframe or
// point unchanged since takes the result; one a local BA moved since, or one added since, is
// moved by its correction (result * snapshot^-1: a keyframe's own, a new keyframe's newest
// optimised keyframe of its world, a point's first observer's). Keyframes and points removed
// since are skipped.
FullBaApplied apply_full_ba(KeyframeGraph& graph, const LocalBaInput& input,
                            const LocalBaResult& result);

}  // namespace hs
