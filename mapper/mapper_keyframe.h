#pragma once
// Plain data of a keyframe as the mapper holds it (see keyframe_from_msg.h for the checks).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "common/core/types.h"
#include "common/features/descriptor_match.h"

namespace hs {

using Descriptor = std::array<uint8_t, 32>;  // ORB, 256 bits

// Hamming distance between two descriptors (0..256).
inline int hamming_distance(const Descriptor& a, const Descriptor& b) {
  return hamming256(a.data(), b.data());
}

struct MapperKeypoint {
  float u = 0.f;  // raw (distorted) cam0 pixel
  float v = 0.f;
  float u_right = -1.f;  // matched raw cam1 pixel, both -1 if none
  float v_right = -1.f;
  float depth = -1.f;  // metres in cam0, -1 if unknown
  int octave = 0;
  float angle = 0.f;      // degrees
  int64_t point_id = -1;  // observed map point, -1 if none
  // Weighed as an ORB detection, not a tracked position: it arrived without a point (a FAST
  // corner on its octave's grid, noisier), so a point it comes to see (triangulated or found
  // again) weighs it less; or it follows a track fused into another point's after a loop was
  // closed (Mapper::ties_across_a_loop).
  bool detected = false;
};

struct MapperKeyframe {
  int64_t id = -1;
  int32_t map_id = 0;
  int64_t prev_id = -1;  // the tracker's previous keyframe, -1 for the first of a map
  NavState state;        // state.t_ns is the keyframe time
  std::vector<MapperKeypoint> keypoints;
  std::vector<Descriptor> descriptors;  // one per keypoint
  // Positions of the observed points as the tracker sent them (keyed by point id).
  std::unordered_map<int64_t, Eigen::Vector3d> point_positions;
  // Strictly increasing samples covering (previous keyframe time, state.t_ns]; the first may lie
  // at or before the previous keyframe time and the last at or after state.t_ns, so both ends
  // can be interpolated.
  std::vector<ImuSample> imu;
};

}  // namespace hs
