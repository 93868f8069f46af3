#pragma once
// Geometric verification of a place candidate (issue 7): the query keyframe's ORB descriptors
// matched with the candidate's stereo keypoints (mutual nearest neighbours, ratio test), the
// query's pose found by PnP RANSAC on the candidate's stereo points, then refined by a
// two-keyframe stereo bundle adjustment (points free, every cam0/cam1 observation of both
// keyframes, Huber loss, a second round without the chi2 outliers). Uses only what the two
// keyframes measured, not their estimated poses: it is the evidence that corrects drift.
#include <Eigen/Geometry>
#include <string>
#include <utility>
#include <vector>

#include "common/calib/camera_calib.h"
#include "mapper/mapper_keyframe.h"

namespace hs {

struct PlaceVerifyOptions {
  int max_hamming = 50;  // descriptor match distance (of 256 bits)
  double ratio = 0.8;    // best under this share of the second best
  double pnp_threshold_px = 3.0;
  int pnp_iterations = 300;
  double pixel_sigma = 1.0;   // keypoint noise at octave 0 (ORB detections)
  double octave_scale = 1.2;  // sigma grows by this per octave
  double chi2 = 5.991;        // per 2-D observation
  double min_depth_m = 0.05;
  int min_inliers = 30;  // matches consistent with the refined pose in every observation
};

struct PlaceMatch {
  bool ok = false;
  Eigen::Isometry3d T_c_q = Eigen::Isometry3d::Identity();  // query body -> candidate body
  int matches = 0;                                          // descriptor matches
  int pnp_inliers = 0;
  int inliers = 0;                                    // after the refinement
  std::vector<std::pair<int, int>> inlier_keypoints;  // (query, candidate) keypoint indices
  std::string message;                                // why not, or what was found
};

PlaceMatch verify_place(const MapperKeyframe& query, const MapperKeyframe& candidate,
                        const StereoCalib& calib, const PlaceVerifyOptions& options);

}  // namespace hs
