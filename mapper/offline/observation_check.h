#pragma once
// How well a set of keyframe poses explains the map's observations: each point seen by enough
// keyframes is triangulated at those poses (common/geometry refine_point) and its
// observations' residuals are summed per camera. At the ground-truth poses of a simulated run
// this checks the front end's measurements: unbiased, and explained by the truth as well as by
// the estimate (a systematic error, e.g. a half-pixel convention, shows as a mean or as a
// truth that fits worse than the estimate). It also measures how a point's cam0 residuals
// correlate from one keyframe to the next: bundle adjustment takes them as independent, and
// errors that follow the track (a patch drifting with the viewpoint) count as information
// they are not.
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>

#include "common/calib/camera_calib.h"
#include "mapper/keyframe_graph.h"

namespace hs {

struct ResidualStats {
  int64_t count = 0;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();  // pixels
  double sum_squared = 0.0;                       // pixels^2, over both axes

  Eigen::Vector2d mean() const { return count ? Eigen::Vector2d(sum / count) : sum; }
  double rms() const { return count ? std::sqrt(sum_squared / count) : 0.0; }  // of the 2D norm
};

struct ObservationCheckOptions {
  int min_keyframes = 3;         // points seen by fewer are skipped
  double max_residual_px = 3.0;  // larger residuals are outliers: counted, not summed
  int iterations = 10;           // Gauss-Newton steps per point
};

// Lag-1 autocorrelation of residuals along tracks: sum r_k . r_k+1 over consecutive inlier
// pairs of each point's cam0 sightings in time order, over the sum of r_k^2. About 0 for
// independent noise (slightly below: the triangulation absorbs some of it), towards 1 for an
// error that drifts slowly along the track.
struct TrackCorrelation {
  double lagged_products = 0.0;  // px^2
  double squares = 0.0;          // px^2
  int64_t pairs = 0;

  double lag1() const { return squares > 0.0 ? lagged_products / squares : 0.0; }
};

struct ObservationCheck {
  std::array<ResidualStats, 2> camera;  // cam0, cam1 (stereo keypoints' right pixel)
  TrackCorrelation track;               // cam0
  int points = 0;                       // triangulated (not singular, in front of every camera)
  int64_t outliers = 0;
};

// Body pose of a keyframe (by its time); nullopt skips the keyframe.
using KeyframePoseLookup = std::function<std::optional<Eigen::Isometry3d>(int64_t t_ns)>;

ObservationCheck check_observations(const KeyframeGraph& graph, const StereoCalib& calib,
                                    const KeyframePoseLookup& T_w_b,
                                    const ObservationCheckOptions& options = {});

}  // namespace hs
