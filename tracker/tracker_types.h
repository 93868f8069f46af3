#pragma once
// What the tracker reports for every frame (published as POSE and TRACKER_STATUS).
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/core/types.h"

namespace hs {

struct Keyframe;
class LocalMap;

// A lost frame for the mapper's atlas (RELOC_REQUEST): its keypoints and stereo points, placed
// at the tracker's IMU-carried guess in the map it was lost in.
struct AtlasQuery {
  int64_t seq = 0;
  int32_t next_map_id = 0;  // the tracker continues in this map id if the atlas places it
  std::shared_ptr<const Keyframe> frame;
  std::shared_ptr<const LocalMap> points;  // the frame's stereo points (ids of their own)
};

// Values match odometry_t's state constants.
enum class TrackState { kInitialising = 0, kTracking = 1, kLost = 2, kRelocalised = 3 };
// Values match tracker_status_t's method constants.
enum class TrackMethod {
  kNone = 0,
  kDirect = 1,
  kDescriptors = 2,
  kRelocalisedReference = 3,
  kRelocalisedGlobal = 4
};

const char* to_string(TrackState state);
const char* to_string(TrackMethod method);

// A point the frame's pose rests on, and how it was found (values match tracker_status_t's
// FEATURE_* constants).
enum class FeatureSource : int8_t { kDirect = 1, kDescriptor = 2, kNew = 3 };
struct FrameFeature {
  Eigen::Vector2f uv;  // raw cam0 pixel
  FeatureSource source;
};

struct FrameResult {
  int64_t t_ns = 0;
  int64_t seq = 0;
  bool accepted = false;  // false: the frame was rejected as bad input (see message)
  TrackState state = TrackState::kInitialising;
  TrackMethod method = TrackMethod::kNone;
  NavState nav;  // body state; valid when accepted and not initialising
  Eigen::Matrix<double, 6, 6> pose_covariance = Eigen::Matrix<double, 6, 6>::Zero();
  float quality = 0.0f;  // 0..1
  int32_t map_id = 0;
  bool is_keyframe = false;
  // The new keyframe, when is_keyframe and the state is known (not while initialising).
  std::shared_ptr<const Keyframe> keyframe;
  std::optional<AtlasQuery> atlas_query;  // lost: ask the mapper's atlas where this frame is
  int tracked_points = 0;
  std::vector<FrameFeature> features;  // tracked_points of them, when tracked
  std::vector<std::pair<std::string, float>> stage_ms;
  float total_ms = 0.0f;
  std::string message;
};

}  // namespace hs
