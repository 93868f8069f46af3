#pragma once
// hs-camera's work: captures one or two V4L2 devices, stamps every frame at mid-exposure on
// CLOCK_MONOTONIC (free-running: from the buffer timestamp; external trigger: from the frame's
// TRIGGER pulse, matched by sequence with a time check), detects dropped frames from sequence
// gaps, pairs left and right, and publishes CAM_STEREO (raw or PNG) with HEARTBEAT. A device that
// is missing or lost is said so and reopened without a restart; nothing unpaired, unmatched or
// wrongly stamped is published.
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "common/core/problem_report.h"
#include "drivers/camera/camera_options.h"
#include "drivers/camera/sequence_tracker.h"
#include "drivers/camera/stereo_pairer.h"
#include "drivers/camera/trigger_matcher.h"
#include "drivers/camera/v4l2_device.h"
#include "hsslam/trigger_t.hpp"

namespace hs {

struct CameraStats {
  int64_t frames[2] = {0, 0};
  int64_t published = 0;
  int64_t bad_frames = 0;  // conversion failed (short buffer) or a timestamp on another clock
  int64_t device_lost = 0;
  int64_t open_failures = 0;
};

class CameraNode {
 public:
  CameraNode(lcm::LCM& lcm, CameraOptions options);
  // Until stop_requested() (install_stop_signals() first).
  void run();
  const CameraStats& stats() const { return stats_; }
  // Dropped frames of device `i` (sequence gaps), over every reopening.
  int64_t dropped(size_t i) const { return devices_.at(i).sequence.stats().dropped; }
  const StereoPairStats& pairing() const { return pairer_.stats(); }
  TriggerMatchStats trigger_matching() const;

 private:
  struct Device {
    std::string path;
    std::unique_ptr<V4l2Device> v4l2;
    SequenceTracker sequence;
    TriggerMatcher matcher;
    int64_t next_open_ns = 0;
  };
  struct WaitingFrame {  // external trigger: a frame waiting for its TRIGGER
    uint32_t sequence;
    int64_t buffer_t_ns;
    int64_t since_ns;
    cv::Mat image;
  };

  void open_missing(int64_t now_ns);
  void read_frame(size_t i, int64_t now_ns);
  void match_waiting(size_t i, int64_t now_ns);
  void stamped(size_t i, uint32_t sequence, int64_t t_ns, cv::Mat image);
  void publish(int64_t t_ns, const cv::Mat& left, const cv::Mat& right);
  void publish_heartbeat(int64_t now_ns);
  static void on_trigger(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                         const hsslam::trigger_t* msg, CameraNode* self);

  lcm::LCM& lcm_;
  CameraOptions options_;
  std::vector<Device> devices_;
  std::vector<std::vector<WaitingFrame>> waiting_;
  StereoPairer pairer_;
  std::map<size_t, cv::Mat> held_;  // images of frames the pairer holds, by handle
  size_t next_handle_ = 0;
  int64_t seq_ = 0;
  ProblemReport problem_{"hs-camera"};
  CameraStats stats_;
};

}  // namespace hs
