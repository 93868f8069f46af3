#pragma once
// The tracker as an LCM component (the hs-tracker process). Subscribes to CAM_STEREO
// (stereo_frame_t), IMU (imu_batch_t) and MAP_UPDATE (map_update_t, from hs-mapper: applied
// between frames) and publishes TRACKER_STATUS per frame, POSE per frame
// that has a state (not while initialising, not for rejected frames: those are only in the
// status), KEYFRAME per keyframe, POSE_IMU at the IMU rate and HEARTBEAT about once a period.
//
// Threads: the thread that runs lcm.handle() (the receive thread) only decodes, queues and
// publishes POSE_IMU; it never waits for tracking. A tracking thread owns the Tracker (not
// thread-safe) and takes IMU batches and frames from a bounded InputQueue in arrival order.
// POSE_IMU is the last tracked state (handed over under a mutex) propagated on the receive side
// with the IMU samples received since. Malformed messages are counted and reported, never fatal.
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "tracker/node/input_queue.h"
#include "tracker/node/node_messages.h"
#include "tracker/node/pose_imu.h"
#include "tracker/tracker_options.h"

namespace hs {

struct NodeStats {
  int64_t frames_received = 0;
  int64_t frames_dropped = 0;  // oldest frames dropped because the queue was full
  int64_t bad_frame_messages = 0;
  int64_t bad_imu_messages = 0;
  int64_t imu_samples_received = 0;
  int64_t tracker_errors = 0;  // exceptions from the tracker (frame skipped)
  int64_t frames_tracked = 0;  // frames handed to the tracker
  int64_t poses_published = 0;
  int64_t pose_imu_published = 0;
  int64_t keyframes_published = 0;
  int64_t map_updates_received = 0;
  int64_t reloc_answers_received = 0;
  int64_t bad_reloc_answer_messages = 0;
  int64_t bad_map_update_messages = 0;
  int64_t map_updates_stale = 0;  // seq not after the previous one (duplicate, reordered)
  int64_t map_updates_lost = 0;   // seq gaps (UDP multicast loses whole messages)
  int64_t mapper_restarts = 0;    // seq back to 0
  double tracking_ms = 0.0;       // summed Tracker::track wall time
};

class TrackerNode {
 public:
  // Subscribes at once (call start() to begin tracking). Node options: options.node; channel
  // names: options.channels.
  TrackerNode(lcm::LCM& lcm, const TrackerOptions& options);
  ~TrackerNode();
  TrackerNode(const TrackerNode&) = delete;
  TrackerNode& operator=(const TrackerNode&) = delete;

  // Starts the tracking thread. Until then inputs only queue up (tests use this to fill it).
  void start();
  // Tracks what is queued, stops the thread and publishes a STOPPING heartbeat. Idempotent.
  void stop();
  // Publishes HEARTBEAT when one is due. Call from the receive thread between lcm.handle()s.
  void poll();

  NodeStats stats() const;
  // Cumulative counters as published: the tracker's, then the node's.
  std::vector<NamedCounter> counters() const;

 private:
  static void on_frame(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                       TrackerNode* self);
  static void on_imu(const lcm::ReceiveBuffer* rbuf, const std::string& channel, TrackerNode* self);
  static void on_map_update(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                            TrackerNode* self);
  void handle_frame(const void* data, size_t size, const std::string& channel);
  void handle_imu(const void* data, size_t size, const std::string& channel);
  void handle_map_update(const void* data, size_t size, const std::string& channel);
  static void on_reloc_answer(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                              TrackerNode* self);
  void handle_reloc_answer(const void* data, size_t size, const std::string& channel);
  void bad_message(int64_t NodeStats::*counter, const std::string& what);
  void publish_pose_imu(const std::vector<ImuSample>& samples);

  void run();
  void track(Tracker& tracker, const StereoFrame& frame);
  void apply(Tracker& tracker, const MapCorrection& correction);
  std::string status_notes();  // drops and bad input since the previous status
  void publish_heartbeat(int8_t state);
  std::vector<NamedCounter> node_counters(const NodeStats& s) const;

  lcm::LCM& lcm_;
  const TrackerOptions options_;
  std::vector<lcm::Subscription*> subscriptions_;
  InputQueue queue_;
  std::thread worker_;
  bool started_ = false;

  // Receive thread only.
  PoseImuPropagator pose_imu_;
  int64_t imu_seen_ = 0;
  int64_t last_update_seq_ = -1;
  int64_t next_heartbeat_ns_ = 0;

  // Tracking thread only: what the previous status already reported.
  int64_t reported_drops_ = 0;
  int64_t reported_bad_ = 0;
  std::string correction_notes_;  // from corrections applied since the previous status

  mutable std::mutex mutex_;  // guards everything below
  NodeStats stats_;
  std::optional<PoseAnchor> new_anchor_;  // from the tracking thread, not yet taken
  std::vector<NamedCounter> tracker_counters_;
  std::optional<TrackState> state_;  // of the last frame that had one
  std::string last_error_;
};

}  // namespace hs
