#pragma once
// The mapper's answer to a lost tracker's relocalisation request (the RELOC_ANSWER channel as
// plain data): where the atlas places the request's frame.
#include <Eigen/Geometry>
#include <cstdint>
#include <string>

namespace hs {

struct RelocAnswer {
  int64_t seq = 0;   // the request's
  int64_t t_ns = 0;  // the request's frame time
  bool found = false;
  // The map id the tracker continues in: the request's next_map_id, which the mapper has
  // joined to the matched keyframe's world.
  int32_t map_id = 0;
  int64_t keyframe_id = -1;  // matched
  Eigen::Isometry3d T_w_b = Eigen::Isometry3d::Identity();
  int inliers = 0;
  std::string message;
};

}  // namespace hs
