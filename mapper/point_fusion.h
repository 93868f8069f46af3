#pragma once
// Map points found again in a keyframe (issue 7). After a loop or a map merge, and on every
// keyframe that revisits an older part of its world, the points around are projected into the
// keyframe's image and matched by descriptor near their projection. A match to a keypoint that
// already sees another point means one point was mapped twice: the two are fused (as ORB-SLAM3's
// loop fusion and neighbour search), which links the revisit to the old keyframes by shared
// points so bundle adjustment holds the two passes together.
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "common/calib/camera_calib.h"
#include "mapper/keyframe_graph.h"

namespace hs {

struct PointFusionOptions {
  int max_hamming =
      30;  // of 256 bits (50: room_mav 0.36 cm instead of 0.30, vehicle 1.93 cm, not 1.41)
  double ratio = 0.8;  // best under this share of the second best
  double radius_px = 4.0;
  // A keypoint with stereo depth matches only a point at about that depth (relative error);
  // 0: no depth check.
  double max_depth_error = 0.1;
  // Points tried: those of the most covisible old keyframes (a revisit) and their neighbourhoods.
  size_t revisited_keyframes = 3;
  size_t neighbourhood_keyframes = 5;
};

struct ProjectedMatch {
  int keypoint = -1;
  int64_t point_id = -1;
};

// Points of a keyframe and its n most covisible keyframes (ascending ids).
std::vector<int64_t> neighbourhood_points(const KeyframeGraph& graph, int64_t keyframe_id,
                                          size_t n);

// `points` projected into `kf`'s cam0 image with the body at T_w_b, each matched with the
// keypoint nearest in descriptor within the radius. `projected`: how many landed in the image.
std::vector<ProjectedMatch> match_projected_points(
    const KeyframeGraph& graph, const MapperKeyframe& kf, const Eigen::Isometry3d& T_w_b,
    const std::vector<int64_t>& points, const StereoCalib& calib, const PointFusionOptions& options,
    int* projected);

// What fusing points into a keyframe did.
struct FusionResult {
  int fused = 0;               // duplicate points merged
  int observations_added = 0;  // free keypoints that now see a point
  // (dropped, kept): the mapper remembers these for points the tracker still names.
  std::vector<std::pair<int64_t, int64_t>> merged;
};

// Matches `points` in keyframe `id` at its current pose and fuses: a free keypoint gains the
// observation; of two points found to be one, a `preferred` one is kept (a loaded map's, which
// must not move), else the one with more observations. ties_as_detections: the dropped point's
// observations are weighted as detections on the kept one (KeyframeGraph::fuse_point).
FusionResult fuse_points_into(KeyframeGraph& graph, int64_t id, const std::vector<int64_t>& points,
                              const StereoCalib& calib, const PointFusionOptions& options,
                              const std::function<bool(int64_t)>& preferred,
                              bool ties_as_detections);

}  // namespace hs
