#pragma once
// The monocular map start (paper Sec. 3.1.1, Eq. 1-4; issue 10): corners of a reference frame
// are followed frame to frame by pyramidal optical flow (forward-backward checked), and once
// they have moved enough the two views are reconstructed (common/geometry/two_view.h: essential
// matrix or homography, cheirality). Until then every frame says why it is still waiting (too
// little flow, too little parallax, an ambiguous motion); a reference that loses most of its
// corners is renewed. The result has the metric scale unknown (|t| = 1): the IMU fixes it.
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/calib/pinhole_radtan.h"
#include "common/geometry/two_view.h"

namespace hs {

struct MonoInitOptions {
  int max_corners = 400;         // in the reference frame
  double corner_quality = 0.01;  // Shi-Tomasi, relative to the strongest corner
  double min_corner_distance_px = 12.0;
  int flow_window_px = 21;
  int flow_levels = 3;
  double max_forward_backward_px = 1.0;  // a corner followed back must land this near
  int min_tracked = 80;                  // fewer corners left: a new reference
  double min_flow_px = 12.0;             // median flow before a reconstruction is tried
  double pixel_sigma = 1.0;              // corner noise: the two-view tests' sigma (over fx)
  TwoViewOptions two_view;               // its sigma is set from pixel_sigma
};

struct MonoInitResult {
  bool ok = false;
  std::string reason;  // while waiting: why
  int64_t ref_t_ns = 0;
  Eigen::Isometry3d T_ref_cur = Eigen::Isometry3d::Identity();  // cam0 frames, |t| = 1
  bool homography = false;
  // Per triangulated corner: its pixels in the two frames and its position in the reference
  // camera frame (unit-baseline scale).
  std::vector<Eigen::Vector2d> uv_ref, uv_cur;
  std::vector<Eigen::Vector3d> p_ref;
  int tracked = 0;  // corners followed from the reference to this frame
  double median_flow_px = 0.0;
};

class MonoInitialiser {
 public:
  MonoInitialiser(const PinholeRadtan& camera, const MonoInitOptions& options = {});

  // Frames in time order (mono8, the camera's size).
  MonoInitResult add_frame(int64_t t_ns, const cv::Mat& image);
  void reset() { ref_.reset(); }

 private:
  struct Reference {
    int64_t t_ns = 0;
    std::vector<cv::Point2f> corners;  // in the reference frame
    std::vector<cv::Point2f> current;  // where they are now
    cv::Mat last_image;
  };
  void start_reference(int64_t t_ns, const cv::Mat& image);

  PinholeRadtan camera_;
  MonoInitOptions options_;
  std::optional<Reference> ref_;
};

}  // namespace hs
