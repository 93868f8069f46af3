#pragma once
// Which keyframes add nothing to the map: ORB-SLAM3's rule, a keyframe is redundant when at
// least 90% of its points are each seen by at least 3 other keyframes at the same or a finer
// scale (octave). Removal itself is KeyframeGraph::remove_keyframe.
#include <cstdint>
#include <vector>

#include "mapper/keyframe_graph.h"

namespace hs {

struct CullingOptions {
  double redundant_ratio = 0.9;  // share of a keyframe's points that must be seen elsewhere
  int min_observers = 3;         // other keyframes (same map id) that must see such a point
  int octave_slack = 0;          // an observer counts up to this many octaves coarser
  size_t keep_recent = 2;        // the graph's newest keyframes are never redundant
  // Never merge two IMU intervals into one longer than this (the preintegration degrades).
  int64_t max_imu_span_ns = 500'000'000;
};

// The redundant keyframes among `candidates` (e.g. a local window), ascending. Decided oldest
// first, each as if the ones already found redundant were gone, so a group of keyframes that
// see the same points is thinned, not removed whole.
std::vector<int64_t> redundant_keyframes(const KeyframeGraph& graph,
                                         std::vector<int64_t> candidates,
                                         const CullingOptions& options);

}  // namespace hs
