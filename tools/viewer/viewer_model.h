#pragma once
// What hs-viewer shows, accumulated from the channels it hears: the latest cam0 image with the
// tracker's features of that frame, the trajectory (POSE), keyframes and map points (KEYFRAME,
// moved and removed by MAP_UPDATE), and the tracker's timing (TRACKER_STATUS). Bounded: images
// and timing keep a short history; the map holds what the mapper has not removed.
#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <map>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "hsslam/keyframe_t.hpp"
#include "hsslam/map_update_t.hpp"
#include "hsslam/odometry_t.hpp"
#include "hsslam/tracker_status_t.hpp"

namespace hs {

struct TrajectoryPoint {
  int64_t t_ns = 0;
  int32_t map_id = 0;
  int8_t state = 0;  // odometry_t constants
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
  double yaw = 0.0;  // heading of the body x axis in the world x-y plane, rad
};

struct KeyframeMark {
  int32_t map_id = 0;
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
  bool corrected = false;  // moved by a MAP_UPDATE
};

// Timing over the recent frames, ms.
struct TimingSummary {
  int frames = 0, keyframes = 0;
  double mean_ms = 0, mean_keyframe_ms = 0, mean_other_ms = 0, max_ms = 0;
  std::vector<std::pair<std::string, double>> mean_stage_ms;  // in pipeline order
};

// A tracked frame: its image and the status the tracker published for it.
struct FrameView {
  cv::Mat image;  // cam0, 8-bit mono
  hsslam::tracker_status_t status;
};

class ViewerModel {
 public:
  explicit ViewerModel(size_t image_history = 40, size_t timing_window = 200);

  void on_image(int64_t t_ns, cv::Mat cam0);
  void on_status(const hsslam::tracker_status_t& status);
  void on_pose(const hsslam::odometry_t& pose);
  void on_keyframe(const hsslam::keyframe_t& keyframe);
  void on_map_update(const hsslam::map_update_t& update);
  void on_bad_message(const std::string& what);  // a message that failed to decode

  // The newest status whose image is here (the image comes first, its status after tracking).
  const std::optional<FrameView>& frame() const { return frame_; }
  const std::optional<hsslam::tracker_status_t>& latest_status() const { return status_; }
  const std::vector<TrajectoryPoint>& trajectory() const { return trajectory_; }
  const std::map<int64_t, KeyframeMark>& keyframes() const { return keyframes_; }
  const std::unordered_map<int64_t, Eigen::Vector3d>& points() const { return points_; }
  TimingSummary timing() const;
  int64_t map_updates() const { return map_updates_; }
  int64_t bad_messages() const { return bad_messages_; }
  const std::string& last_bad_message() const { return last_bad_; }
  // The first tracker time heard (TRACKER_STATUS or POSE), for times shown relative to it.
  int64_t first_t_ns() const { return first_t_ns_; }
  // Bumped by every change, so a renderer can skip drawing an unchanged view.
  uint64_t version() const { return version_; }

 private:
  size_t image_history_, timing_window_;
  std::deque<std::pair<int64_t, cv::Mat>> images_;
  std::deque<hsslam::tracker_status_t> pending_;  // statuses whose image has not come yet
  std::optional<FrameView> frame_;
  std::optional<hsslam::tracker_status_t> status_;
  std::deque<hsslam::tracker_status_t> timing_;
  std::vector<TrajectoryPoint> trajectory_;
  std::map<int64_t, KeyframeMark> keyframes_;
  std::unordered_map<int64_t, Eigen::Vector3d> points_;
  int64_t map_updates_ = 0, bad_messages_ = 0, first_t_ns_ = 0;
  std::string last_bad_;
  uint64_t version_ = 0;
};

}  // namespace hs
