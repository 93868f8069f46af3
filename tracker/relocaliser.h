#pragma once
// Relocalisation after a tracking failure (Algorithm 1): first against the reference keyframe
// (Eq. 7: ORB matching + PnP), then globally (Eq. 8: keyframes ranked by the photometric error
// between their stored thumbnail and the current image, best candidates verified by ORB
// matching + PnP). Either way the pose is refined by the pose-only optimiser.
#include <string>
#include <vector>

#include "tracker/keyframe_builder.h"
#include "tracker/local_map.h"
#include "tracker/pose_opt.h"
#include "tracker/tracker_options.h"

namespace hs {

struct RelocResult {
  bool ok = false;
  NavState nav;  // pose filled when ok; velocity and biases copied from the guess
  int inliers = 0;
  int64_t keyframe_id = -1;
  std::vector<TrackedObservation> tracked;  // inlier map points in the current frame
  std::string message;
};

class Relocaliser {
 public:
  Relocaliser(const TrackerOptions& options, const PoseOptimizer& optimizer)
      : options_(options), optimizer_(optimizer) {}

  RelocResult against_keyframe(const Keyframe& kf, const OrbFeatures& current,
                               const NavState& guess, const LocalMap& map) const;
  RelocResult global(const cv::Mat& thumbnail, const OrbFeatures& current, const NavState& guess,
                     const LocalMap& map, int candidates = 3) const;

 private:
  const TrackerOptions& options_;
  const PoseOptimizer& optimizer_;
};

// Zero-mean, unit-variance sum of squared differences per pixel (0: identical up to gain and
// offset, ~2: uncorrelated). Images must have the same size.
double photometric_distance(const cv::Mat& a, const cv::Mat& b);

}  // namespace hs
