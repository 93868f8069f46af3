#pragma once
// Finds the cam1 correspondences of cam0 keypoints at a keyframe and triangulates them.
// Pyramidal optical flow from left to right (no descriptors on cam1), checked by flowing back
// and by the epipolar geometry of the calibrated, unrectified rig.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "common/calib/camera_calib.h"
#include "tracker/stereo_refine.h"

namespace hs {

struct StereoMatchOptions {
  int window = 15;  // optical-flow window, pixels
  int pyramid_levels = 3;
  double init_depth_m = 4.0;     // depth used to predict the right pixel
  double max_epipolar_px = 1.0;  // reprojection error allowed in each camera
  double max_backflow_px = 0.5;  // left -> right -> left round trip
  double min_depth_m = 0.15;
  double max_depth_m = 40.0;
  // Refine each flow match with the disparity free to vary across the window (see
  // stereo_refine.h); a match the refinement cannot place keeps its flow result. Measured
  // (tracker alone): room_mav 20 s 0.17 cm (0.41 off), vehicle_loop 50 s seeds 1-4 3.98 cm mean
  // (4.21 off); keyframe stereo 4.6 ms instead of 2.0.
  bool refine_slanted = true;
  SlantedRefineOptions slanted;
};

struct StereoMatch {
  bool valid = false;
  Eigen::Vector2d uv1 = Eigen::Vector2d::Constant(-1);  // pixel in cam1
  Eigen::Vector3d p_c0 = Eigen::Vector3d::Zero();       // point in cam0 frame
  // Unit normal (cam0 frame) of the surface around the point, from the disparity's change
  // across the window; zero when not measured.
  Eigen::Vector3d n_c0 = Eigen::Vector3d::Zero();
};

class StereoMatcher {
 public:
  StereoMatcher(const StereoCalib& calib, const StereoMatchOptions& options);
  std::vector<StereoMatch> match(const cv::Mat& image0, const cv::Mat& image1,
                                 const std::vector<Eigen::Vector2d>& uv0) const;

 private:
  std::optional<Eigen::Vector3d> triangulate(const Eigen::Vector2d& uv0,
                                             const Eigen::Vector2d& uv1) const;
  Eigen::Vector3d surface_normal(const Eigen::Vector2d& uv0, const SlantedMatch& m,
                                 const Eigen::Vector2d& e) const;
  StereoCalib calib_;
  StereoMatchOptions options_;
  Eigen::Isometry3d T_c0_c1_;
  Eigen::Isometry3d T_c1_c0_;
};

}  // namespace hs
