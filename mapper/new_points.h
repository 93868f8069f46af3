#pragma once
// New map points from the mapper itself (ORB-SLAM3's local mapping does the same): keypoints
// of a new keyframe that see no point are matched by descriptor with the free keypoints of its
// most covisible keyframes, along the epipolar line their poses give, and triangulated. A match
// is kept only with enough parallax, in front of both cameras, within a few pixels of both
// keypoints, and at distances that agree with the two keypoints' pyramid levels. The tracker
// makes its points from stereo matches; these are the ones it could not match in the right
// image (too far, outside its view, or occluded) but two keyframes' baseline can place.
#include <cstdint>
#include <vector>

#include "common/calib/camera_calib.h"
#include "mapper/keyframe_graph.h"

namespace hs {

struct NewPointOptions {
  // Matched with this many most covisible keyframes; 0: off. Off by default for stereo: the
  // tracker's stereo points leave little for two keyframes to place (measured in
  // config/mapper.yaml).
  size_t covisible_keyframes = 0;
  int max_hamming = 50;              // descriptor distance of a match, of 256 bits
  double ratio = 0.8;                // best distance below this share of the second best
  double epipolar_px = 2.0;          // distance from the epipolar line at octave 0
  double min_parallax_deg = 1.0;     // angle between the two rays
  double max_reprojection_px = 2.0;  // in both keyframes, at octave 0
  double octave_scale = 1.2;         // ORB pyramid scale: tolerances grow by it per octave
  // Distance ratio of the point from the two cameras against their octaves' scale ratio.
  double scale_ratio_factor = 1.5;
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
