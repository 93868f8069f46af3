#pragma once
// New points from two views with known poses: keypoints that see no point yet are matched by
// descriptor along the epipolar line the poses give, and triangulated. A match is kept only
// with enough parallax, in front of both cameras, within a few pixels of both keypoints, and at
// distances that agree with the two keypoints' pyramid levels. The mapper places the points its
// keyframes' stereo could not (mapper/new_points.h); a mono tracker makes all its points so.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "common/calib/pinhole_radtan.h"

namespace hs {

struct EpipolarPointOptions {
  int max_hamming = 50;              // descriptor distance of a match, of 256 bits
  double ratio = 0.8;                // best distance below this share of the second best
  double epipolar_px = 2.0;          // distance from the epipolar line at octave 0
  double min_parallax_deg = 1.0;     // angle between the two rays
  double max_reprojection_px = 2.0;  // in both views, at octave 0
  double octave_scale = 1.2;         // ORB pyramid scale: tolerances grow by it per octave
  // Distance ratio of the point from the two cameras against their octaves' scale ratio.
  double scale_ratio_factor = 1.5;
};

// One view's keypoints that see no point yet.
class FreeKeypoints {
 public:
  FreeKeypoints(const Eigen::Isometry3d& T_w_c, const PinholeRadtan& camera)
      : T_w_c_(T_w_c), camera_(&camera) {}
  // `index` is the caller's (its keypoint index); `descriptor` 32 bytes that must outlive this.
  void add(int index, const Eigen::Vector2d& uv, int octave, const uint8_t* descriptor);

  struct Keypoint {
    int index;
    Eigen::Vector2d uv;  // raw pixel
    int octave;
    const uint8_t* descriptor;
    Eigen::Vector3d f_c;  // unit bearing in the camera
    Eigen::Vector3d f_w;  // ... in the world
  };
  const std::vector<Keypoint>& keypoints() const { return keypoints_; }
  const Eigen::Isometry3d& T_w_c() const { return T_w_c_; }

 private:
  Eigen::Isometry3d T_w_c_;
  const PinholeRadtan* camera_;
  std::vector<Keypoint> keypoints_;
};

// A triangulated match: positions in the two views' keypoint lists.
struct EpipolarPoint {
  size_t a = 0, b = 0;
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
};

// Points for a's keypoints not yet `used_a` (sized as a's keypoints; the matched ones are set),
// each of b's keypoints used once. Both views through the same camera.
std::vector<EpipolarPoint> triangulate_epipolar(const FreeKeypoints& a, const FreeKeypoints& b,
                                                const PinholeRadtan& camera,
                                                const EpipolarPointOptions& options,
                                                std::vector<bool>& used_a);

}  // namespace hs
