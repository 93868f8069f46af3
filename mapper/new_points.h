#pragma once
// New map points from the mapper itself (ORB-SLAM3's local mapping does the same): keypoints
// of a new keyframe that see no point are matched with the free keypoints of its most
// covisible keyframes along the epipolar line (common/features/epipolar_points.h). The tracker
// makes its points from stereo matches; these are the ones it could not match in the right
// image (too far, outside its view, or occluded) but two keyframes' baseline can place.
#include <cstdint>
#include <vector>

#include "common/calib/camera_calib.h"
#include "common/features/epipolar_points.h"
#include "mapper/keyframe_graph.h"

namespace hs {

struct NewPointOptions : EpipolarPointOptions {
  // Matched with this many most covisible keyframes; 0: off. Off by default for stereo: the
  // tracker's stereo points leave little for two keyframes to place (measured in
  // config/mapper.yaml).
  size_t covisible_keyframes = 0;
};

// What a new point would be: its position and the two keypoints that see it.
struct NewPoint {
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
  Observation a, b;
};

// Points for keyframe `id`'s free keypoints (each keypoint used once); nothing is added to
// the graph.
std::vector<NewPoint> triangulate_new_points(const KeyframeGraph& graph, int64_t id,
                                             const StereoCalib& calib,
                                             const NewPointOptions& options);

}  // namespace hs
