#pragma once
// Timestamp association as evo's sync.associate_trajectories: every pose of the shorter
// trajectory (the estimate when both have the same length) is paired with the pose of the other
// whose time is nearest (earlier one on ties), after adding `t_offset_ns` to the estimate's
// stamps; pairs further apart than `t_max_diff_ns` are dropped. A pose of the longer trajectory
// can end up in two pairs.
#include <cstdint>

#include "common/eval/trajectory.h"

namespace hs {

struct Association {
  Trajectory gt;  // gt.poses[i] pairs with est.poses[i]; each keeps its own timestamps
  Trajectory est;
};

// Throws InputError when no pair is found.
Association associate(const Trajectory& gt, const Trajectory& est, int64_t t_max_diff_ns,
                      int64_t t_offset_ns = 0);

}  // namespace hs
