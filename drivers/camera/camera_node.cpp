#include "drivers/camera/camera_node.h"

#include <poll.h>

#include <cstdio>

#include "common/core/monotonic_clock.h"
#include "common/core/stop_signal.h"
#include "common/lcm/process_loop.h"
#include "drivers/camera/frame_time.h"

namespace hs {
namespace {

constexpr int64_t kDegradedHoldNs = 10'000'000'000;  // a problem keeps HEARTBEAT DEGRADED this long

}  // namespace

CameraNode::CameraNode(lcm::LCM& lcm, CameraOptions options)
    : lcm_(lcm), options_(std::move(options)), pairer_(options_.max_stereo_skew_ns) {
  for (const std::string& path : options_.devices)
    devices_.push_back({path, nullptr, SequenceTracker(), TriggerMatcher(options_.trigger), 0});
  waiting_.resize(devices_.size());
  if (options_.mode == TriggerMode::kExternal)
    lcm_.subscribeFunction(options_.channels.trigger, &CameraNode::on_trigger, this);
}

TriggerMatchStats CameraNode::trigger_matching() const {
  TriggerMatchStats sum;
  for (const Device& d : devices_) sum += d.matcher.stats();
  return sum;
}

void CameraNode::on_trigger(const lcm::ReceiveBuffer*, const std::string&,
                            const hsslam::trigger_t* msg, CameraNode* self) {
  for (Device& d : self->devices_) d.matcher.add_trigger(msg->seq, msg->t_ns);
}

void CameraNode::open_missing(int64_t now_ns) {
  for (Device& d : devices_) {
    if (d.v4l2 || now_ns < d.next_open_ns) continue;
    try {
      d.v4l2 = std::make_unique<V4l2Device>(d.path, options_.format);
      std::fprintf(stderr, "hs-camera: %s opened\n", d.path.c_str());
      d.sequence.reset();
      d.matcher.reset();
      problem_.clear();
    } catch (const std::exception& e) {
      ++stats_.open_failures;
      problem_.set(std::string(e.what()) + "; retrying", now_ns);
      d.next_open_ns = now_ns + options_.reconnect_period_ns;
    }
  }
}

void CameraNode::publish(int64_t t_ns, const cv::Mat& left, const cv::Mat& right) {
  StereoFrame frame;
  frame.t_ns = t_ns;
  frame.seq = seq_++;
  frame.cam0 = left;
  frame.cam1 = right;
  const hsslam::stereo_frame_t msg = frame_to_msg(frame, options_.encoding);
  lcm_.publish(options_.channels.cam_stereo, &msg);
  ++stats_.published;
}

void CameraNode::stamped(size_t i, uint32_t sequence, int64_t t_ns, cv::Mat image) {
  if (options_.side_by_side) {
    const int half = image.cols / 2;
    publish(t_ns, image.colRange(0, half).clone(), image.colRange(half, 2 * half).clone());
    return;
  }
  if (devices_.size() == 1) {
    publish(t_ns, image, cv::Mat());
    return;
  }
  const size_t handle = next_handle_++;
  held_[handle] = std::move(image);
  std::vector<SideFrame> dropped;
  for (const auto& [l, r] : pairer_.add(static_cast<int>(i), {sequence, t_ns, handle}, &dropped)) {
    publish(l.t_ns, held_.at(l.index), held_.at(r.index));
    held_.erase(l.index);
    held_.erase(r.index);
  }
  for (const SideFrame& f : dropped) held_.erase(f.index);
}

void CameraNode::match_waiting(size_t i, int64_t now_ns) {
  std::vector<WaitingFrame>& w = waiting_[i];
  size_t done = 0;
  for (; done < w.size(); ++done) {
    const WaitingFrame& f = w[done];
    const TriggerMatch m =
        devices_[i].matcher.match(f.sequence, f.buffer_t_ns, now_ns - f.since_ns);
    if (m.decision == TriggerDecision::kWait) break;  // later frames wait behind it
    if (m.decision == TriggerDecision::kMatched)
      stamped(i, f.sequence,
              mid_exposure_from_trigger_ns(m.trigger_t_ns, options_.format.exposure_ns), f.image);
    else if (m.decision == TriggerDecision::kNoTrigger)
      problem_.set(devices_[i].path +
                       ": frames without a TRIGGER pulse (is hs-trigger running?): "
                       "dropped",
                   now_ns);
    else
      problem_.set(devices_[i].path + ": a frame and its TRIGGER pulse disagree in time: dropped",
                   now_ns);
  }
  w.erase(w.begin(), w.begin() + static_cast<std::ptrdiff_t>(done));
}

void CameraNode::read_frame(size_t i, int64_t now_ns) {
  Device& d = devices_[i];
  V4l2Frame f;
  const V4l2Device::Status status = d.v4l2->dequeue(0, &f);
  if (status == V4l2Device::Status::kTimeout) return;
  if (status == V4l2Device::Status::kLost) {
    problem_.set(d.path + " lost (" + d.v4l2->lost_reason() + "); retrying", now_ns);
    d.v4l2.reset();
    ++stats_.device_lost;
    waiting_[i].clear();
    pairer_.reset();
    held_.clear();
    d.next_open_ns = now_ns + options_.reconnect_period_ns;
    return;
  }
  cv::Mat image;
  try {
    image = to_mono8(d.v4l2->format(), f.data, f.bytes_used, d.v4l2->width(), d.v4l2->height(),
                     d.v4l2->bytes_per_line());
  } catch (const std::exception& e) {
    ++stats_.bad_frames;
    problem_.set(d.path + ": " + e.what(), now_ns);
  }
  d.v4l2->requeue(f.index);  // the copy is ours: give the buffer back at once
  if (d.sequence.add(f.sequence) < 0 || image.empty()) return;
  ++stats_.frames[i];
  if (options_.mode == TriggerMode::kExternal) {
    waiting_[i].push_back({f.sequence, f.time.t_ns, now_ns, std::move(image)});
    match_waiting(i, now_ns);
    return;
  }
  try {
    stamped(i, f.sequence, mid_exposure_ns(f.time, d.v4l2->exposure_ns(), options_.readout_ns),
            std::move(image));
  } catch (const std::exception& e) {
    ++stats_.bad_frames;
    problem_.set(d.path + ": " + e.what(), now_ns);
  }
}

void CameraNode::publish_heartbeat(int64_t now_ns) {
  bool all_open = true;
  for (const Device& d : devices_) all_open &= d.v4l2 != nullptr;
  hsslam::heartbeat_t hb = heartbeat_header(
      "hs-camera", !all_open
                       ? hsslam::heartbeat_t::ERROR
                       : (problem_.recent(now_ns, kDegradedHoldNs) ? hsslam::heartbeat_t::DEGRADED
                                                                   : hsslam::heartbeat_t::OK));
  hb.message = problem_.empty() ? "capturing" : "capturing; last problem: " + problem_.text();
  if (!all_open) hb.message = problem_.text();
  hb.queue_names = {"held_images"};
  hb.queue_depths = {static_cast<int32_t>(held_.size())};
  hb.num_queues = 1;
  const StereoPairStats& p = pairer_.stats();
  const TriggerMatchStats t = trigger_matching();
  add_counters(hb, std::vector<std::pair<std::string, int64_t>>{
                       {"frames_left", stats_.frames[0]},
                       {"frames_right", stats_.frames[1]},
                       {"dropped_left", dropped(0)},
                       {"dropped_right", devices_.size() > 1 ? dropped(1) : 0},
                       {"published", stats_.published},
                       {"unpaired_left", p.unpaired_left},
                       {"unpaired_right", p.unpaired_right},
                       {"trigger_matched", t.matched},
                       {"frames_without_trigger", t.frames_without_trigger},
                       {"triggers_without_frame", t.triggers_without_frame},
                       {"trigger_time_mismatches", t.time_mismatches},
                       {"trigger_relocks", t.relocks},
                       {"bad_frames", stats_.bad_frames},
                       {"device_lost", stats_.device_lost},
                       {"open_failures", stats_.open_failures}});
  lcm_.publish(options_.channels.heartbeat, &hb);
}

void CameraNode::run() {
  int64_t next_heartbeat = 0;
  while (!stop_requested()) {
    int64_t now = monotonic_ns();
    open_missing(now);
    std::vector<pollfd> fds;
    std::vector<size_t> which;
    for (size_t i = 0; i < devices_.size(); ++i) {
      if (!devices_[i].v4l2) continue;
      fds.push_back({devices_[i].v4l2->fd(), POLLIN, 0});
      which.push_back(i);
    }
    fds.push_back({lcm_.getFileno(), POLLIN, 0});
    ::poll(fds.data(), fds.size(), 20);
    now = monotonic_ns();
    if (fds.back().revents & POLLIN) lcm_.handleTimeout(0);
    for (size_t k = 0; k < which.size(); ++k)
      if (fds[k].revents) read_frame(which[k], now);
    for (size_t i = 0; i < devices_.size(); ++i) match_waiting(i, now);  // late TRIGGERs
    if (now >= next_heartbeat) {
      publish_heartbeat(now);
      next_heartbeat = now + options_.heartbeat_period_ns;
    }
  }
}

}  // namespace hs
