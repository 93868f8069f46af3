#pragma once
// A mapper's correction of the tracker's map (the MAP_UPDATE channel as plain data): refined
// keyframe states and point positions, the points the mapper found to be outliers, gravity.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "common/core/types.h"

namespace hs {

struct KeyframeCorrection {
  int64_t id = -1;
  NavState state;  // state.t_ns is the keyframe time
};

struct PointCorrection {
  int64_t id = -1;
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
};

struct MapCorrection {
  int64_t seq = 0;     // increases by one per correction a mapper sends
  int32_t map_id = 0;  // the tracker map id the keyframes belong to
  int64_t t_ns = 0;    // time of the newest keyframe covered
  std::vector<KeyframeCorrection> keyframes;
  std::vector<PointCorrection> points;
  std::vector<int64_t> removed_points;
  // Gravity in the tracker's world as the mapper estimates it: the world was levelled at rest
  // with a biased accelerometer, and the corrected states are consistent with this gravity, not
  // with the world's -z. Zero: the mapper does not estimate it.
  Eigen::Vector3d g_w = Eigen::Vector3d::Zero();
};

}  // namespace hs
