#pragma once
// Turns a tracked frame into a keyframe (Algorithm 1, UMWK): ORB features are extracted here,
// and only here in hybrid mode; points tracked by direct alignment are attached to keypoints
// (getting descriptors for the mapper and relocalisation), and new points are triangulated
// from the stereo pair, or on a mono rig with the previous keyframe.
#include <memory>
#include <vector>

#include "common/dataset/stereo_frame.h"
#include "tracker/local_map.h"
#include "tracker/orb_extractor.h"
#include "tracker/stage_timer.h"
#include "tracker/stereo_matcher.h"
#include "tracker/tracker_options.h"

namespace hs {

struct TrackedObservation {
  int64_t point_id = -1;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  // cam0 pixel in the current frame
};

struct KeyframeBuildStats {
  int attached = 0;    // tracked points given a keypoint
  int new_points = 0;  // triangulated from the stereo pair (mono: with the previous keyframe)
  int stereo_matched = 0;
  int refined = 0;  // mono: tracked points placed again from all their sightings
};

class KeyframeBuilder {
 public:
  explicit KeyframeBuilder(const TrackerOptions& options);

  // `features`: ORB features already extracted from this frame (every-frame mode), or null.
  // New map points are added to `map` (mono: matched with its latest keyframe); the keyframe
  // is returned, not yet added to it. With a
  // timer, the ORB and stereo steps are timed as stages of their own.
  std::shared_ptr<Keyframe> build(const StereoFrame& frame, const ImagePyramid& pyramid,
                                  const NavState& nav,
                                  const std::vector<TrackedObservation>& tracked,
                                  const OrbFeatures* features, LocalMap& map,
                                  KeyframeBuildStats* stats, StageTimer* timer = nullptr) const;

  const OrbExtractor& orb() const { return orb_; }
  // Also match the keyframe's tracked points in cam1: only a mapper uses those stereo views
  // (about 3 ms more per keyframe), the tracker needs stereo only for new points.
  void set_stereo_for_tracked(bool on) { stereo_for_tracked_ = on; }

 private:
  void add_stereo_points(const StereoFrame& frame, Keyframe& kf, LocalMap& map,
                         KeyframeBuildStats& st) const;
  void add_mono_points(Keyframe& kf, LocalMap& map, KeyframeBuildStats& st) const;
  // Mono: the keyframe's tracked points seen once more, and placed again from all sightings.
  void refine_mono_points(const Keyframe& kf, LocalMap& map, KeyframeBuildStats& st) const;
  // Keypoints of `kf` seeing no point, strongest first, in cells of the image no tracked point
  // covers (one per cell), up to the per-keyframe budget.
  std::vector<int> new_point_candidates(const Keyframe& kf, int width, int height) const;
  void add_point(Keyframe& kf, int keypoint, const Eigen::Vector3d& p_w, LocalMap& map,
                 KeyframeBuildStats& st,
                 const Eigen::Vector3d& n_w = Eigen::Vector3d::Zero()) const;

  const TrackerOptions& options_;
  OrbExtractor orb_;
  StereoMatcher stereo_;
  bool stereo_for_tracked_ = false;
};

// ORB's intensity-centroid orientation (degrees) of the patch around `uv`.
float intensity_centroid_angle(const cv::Mat& image, const cv::Point2f& uv, int radius = 15);

}  // namespace hs
