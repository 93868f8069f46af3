#include "tracker/node/tracker_node.h"

#include <exception>

#include "common/core/monotonic_clock.h"
#include "common/lcm/convert.h"
#include "common/lcm/decode.h"
#include "common/lcm/process_loop.h"
#include "hsslam/heartbeat_t.hpp"
#include "hsslam/map_update_t.hpp"
#include "hsslam/reloc_answer_t.hpp"

namespace hs {
namespace {

std::string plural(int64_t n, const char* what) {
  return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
}

}  // namespace

TrackerNode::TrackerNode(lcm::LCM& lcm, const TrackerOptions& options)
    : lcm_(lcm),
      options_(options),
      queue_(static_cast<size_t>(options.node.frame_queue_size)),
      pose_imu_(options.imu, options.imu_buffer.keep_ns),
      tracker_counters_(tracker_counters({}, {})) {
  // Plain-function handlers: GCC 12 UBSan's vptr check breaks LCM's member-function dispatch.
  subscriptions_.push_back(
      lcm_.subscribeFunction(options_.channels.cam_stereo, &TrackerNode::on_frame, this));
  subscriptions_.push_back(
      lcm_.subscribeFunction(options_.channels.imu, &TrackerNode::on_imu, this));
  subscriptions_.push_back(
      lcm_.subscribeFunction(options_.channels.map_update, &TrackerNode::on_map_update, this));
  subscriptions_.push_back(
      lcm_.subscribeFunction(options_.channels.reloc_answer, &TrackerNode::on_reloc_answer, this));
}

TrackerNode::~TrackerNode() {
  stop();
  for (lcm::Subscription* s : subscriptions_) lcm_.unsubscribe(s);
}

void TrackerNode::start() {
  if (started_) return;
  started_ = true;
  worker_ = std::thread([this] { run(); });
  publish_heartbeat(hsslam::heartbeat_t::STARTING);
  next_heartbeat_ns_ = monotonic_ns() + options_.node.heartbeat_period_ns;
}

void TrackerNode::stop() {
  queue_.close();
  if (!worker_.joinable()) return;
  worker_.join();
  publish_heartbeat(hsslam::heartbeat_t::STOPPING);
  started_ = false;  // STOPPING is the last heartbeat: poll() publishes no more
}

void TrackerNode::poll() {
  const int64_t now = monotonic_ns();
  if (!started_ || now < next_heartbeat_ns_) return;
  next_heartbeat_ns_ = now + options_.node.heartbeat_period_ns;
  std::optional<TrackState> state;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    state = state_;
  }
  publish_heartbeat(!state                        ? hsslam::heartbeat_t::STARTING
                    : *state == TrackState::kLost ? hsslam::heartbeat_t::DEGRADED
                                                  : hsslam::heartbeat_t::OK);
}

NodeStats TrackerNode::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

std::vector<NamedCounter> TrackerNode::counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<NamedCounter> all = tracker_counters_;
  for (NamedCounter& c : node_counters(stats_)) all.push_back(std::move(c));
  return all;
}

std::vector<NamedCounter> TrackerNode::node_counters(const NodeStats& s) const {
  return {{"frames_received", s.frames_received},
          {"frames_dropped_queue_full", s.frames_dropped},
          {"bad_frame_messages", s.bad_frame_messages},
          {"bad_imu_messages", s.bad_imu_messages},
          {"imu_samples_received", s.imu_samples_received},
          {"tracker_errors", s.tracker_errors},
          {"map_updates_received", s.map_updates_received},
          {"reloc_answers_received", s.reloc_answers_received},
          {"bad_reloc_answer_messages", s.bad_reloc_answer_messages},
          {"bad_map_update_messages", s.bad_map_update_messages},
          {"map_updates_stale", s.map_updates_stale},
          {"map_updates_lost", s.map_updates_lost},
          {"mapper_restarts", s.mapper_restarts},
          {"pose_imu_published", s.pose_imu_published}};
}

// ---- receive thread -----------------------------------------------------------------------

void TrackerNode::on_frame(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                           TrackerNode* self) {
  self->handle_frame(rbuf->data, rbuf->data_size, channel);
}

void TrackerNode::on_imu(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                         TrackerNode* self) {
  self->handle_imu(rbuf->data, rbuf->data_size, channel);
}

void TrackerNode::on_map_update(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                                TrackerNode* self) {
  self->handle_map_update(rbuf->data, rbuf->data_size, channel);
}

void TrackerNode::on_reloc_answer(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                                  TrackerNode* self) {
  self->handle_reloc_answer(rbuf->data, rbuf->data_size, channel);
}

void TrackerNode::bad_message(int64_t NodeStats::*counter, const std::string& what) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++(stats_.*counter);
  last_error_ = what;
}

void TrackerNode::handle_frame(const void* data, size_t size, const std::string& channel) {
  // No exception may leave an LCM callback (it unwinds through C code).
  StereoFrame frame;
  try {
    frame = frame_from_msg(decode_message<hsslam::stereo_frame_t>(data, size, channel), channel);
  } catch (const std::exception& e) {
    bad_message(&NodeStats::bad_frame_messages, e.what());
    return;
  }
  const bool dropped = queue_.push_frame(std::move(frame));
  std::lock_guard<std::mutex> lock(mutex_);
  ++stats_.frames_received;
  stats_.frames_dropped += dropped;
}

void TrackerNode::handle_imu(const void* data, size_t size, const std::string& channel) {
  std::vector<ImuSample> samples;
  try {
    samples = imu_batch_from_msg(decode_message<hsslam::imu_batch_t>(data, size, channel), channel);
  } catch (const std::exception& e) {
    bad_message(&NodeStats::bad_imu_messages, e.what());
    return;
  }
  queue_.push_imu(samples);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.imu_samples_received += static_cast<int64_t>(samples.size());
  }
  publish_pose_imu(samples);
}

void TrackerNode::handle_map_update(const void* data, size_t size, const std::string& channel) {
  MapCorrection c;
  try {
    c = map_correction_from_msg(decode_message<hsslam::map_update_t>(data, size, channel), channel);
  } catch (const std::exception& e) {
    bad_message(&NodeStats::bad_map_update_messages, e.what());
    return;
  }
  // One mapper numbers its updates 0, 1, 2, ...: a repeat or a step back is stale (its
  // keyframes' states were superseded), a jump means updates were lost, and 0 after more is a
  // restarted mapper.
  std::lock_guard<std::mutex> lock(mutex_);
  ++stats_.map_updates_received;
  if (c.seq == 0 && last_update_seq_ > 0) {
    ++stats_.mapper_restarts;
  } else if (c.seq <= last_update_seq_) {
    ++stats_.map_updates_stale;
    return;
  } else {
    stats_.map_updates_lost += c.seq - last_update_seq_ - 1;
  }
  last_update_seq_ = c.seq;
  queue_.push_correction(std::move(c));
}

void TrackerNode::handle_reloc_answer(const void* data, size_t size, const std::string& channel) {
  RelocAnswer a;
  try {
    a = reloc_answer_from_msg(decode_message<hsslam::reloc_answer_t>(data, size, channel), channel);
  } catch (const std::exception& e) {
    bad_message(&NodeStats::bad_reloc_answer_messages, e.what());
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.reloc_answers_received;
  }
  queue_.push_answer(std::move(a));  // the tracker matches it with its pending request
}

void TrackerNode::publish_pose_imu(const std::vector<ImuSample>& samples) {
  std::optional<PoseAnchor> anchor;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    anchor.swap(new_anchor_);
  }
  if (anchor) pose_imu_.set_anchor(*anchor);
  int64_t published = 0;
  for (const ImuSample& s : samples) {
    pose_imu_.add(s);
    if (imu_seen_++ % options_.node.pose_imu_decimation != 0) continue;
    const std::optional<NavState> x = pose_imu_.propagate(s.t_ns);
    if (!x) continue;
    const PoseAnchor& a = *pose_imu_.anchor();
    // seq: the index of the IMU sample (in arrival order) the state is propagated to.
    const hsslam::odometry_t msg =
        odometry_to_msg(*x, imu_seen_ - 1, a.map_id, static_cast<int8_t>(a.state), a.quality);
    lcm_.publish(options_.channels.pose_imu, &msg);
    ++published;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  stats_.pose_imu_published += published;
}

// ---- tracking thread ----------------------------------------------------------------------

void TrackerNode::run() {
  Tracker tracker(options_);
  NodeInput input;
  while (queue_.pop(input)) {
    if (auto* samples = std::get_if<std::vector<ImuSample>>(&input)) {
      for (const ImuSample& s : *samples) tracker.add_imu(s);  // rejections: imu_counters()
    } else if (auto* correction = std::get_if<MapCorrection>(&input)) {
      tracker.set_mapper_present();  // a mapper is listening to KEYFRAME
      apply(tracker, *correction);
    } else if (auto* answer = std::get_if<RelocAnswer>(&input)) {
      const std::string note = tracker.apply(*answer);
      correction_notes_ += (correction_notes_.empty() ? "" : "; ") + note;
    } else {
      track(tracker, std::get<StereoFrame>(input));
    }
  }
}

void TrackerNode::track(Tracker& tracker, const StereoFrame& frame) {
  FrameResult r;
  try {
    r = tracker.track(frame);
  } catch (const std::exception& e) {
    bad_message(&NodeStats::tracker_errors,
                "frame " + std::to_string(frame.seq) + ": tracker error: " + e.what());
    return;
  }
  const bool has_state = r.accepted && r.state != TrackState::kInitialising;
  if (has_state) {
    const hsslam::odometry_t pose = pose_msg(r);
    lcm_.publish(options_.channels.pose, &pose);
  }
  if (r.keyframe) {
    const hsslam::keyframe_t kf = keyframe_msg(*r.keyframe, tracker.map(), r.map_id);
    lcm_.publish(options_.channels.keyframe, &kf);
  }
  if (r.atlas_query) {
    const hsslam::reloc_request_t request = reloc_request_msg(*r.atlas_query, r.map_id);
    lcm_.publish(options_.channels.reloc_request, &request);
  }
  std::vector<NamedCounter> counters = tracker_counters(tracker.counters(), tracker.imu_counters());
  std::string message = r.message;
  NodeStats stats;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    tracker_counters_ = counters;
    ++stats_.frames_tracked;
    stats_.tracking_ms += r.total_ms;
    stats_.poses_published += has_state;
    stats_.keyframes_published += r.keyframe != nullptr;
    if (has_state) {
      new_anchor_ = PoseAnchor{r.nav, r.state, r.map_id, r.quality, tracker.gravity_w()};
      new_anchor_->nav.t_ns = r.t_ns;
      state_ = r.state;
    }
    stats = stats_;
  }
  const std::string notes = status_notes();
  if (!notes.empty()) message += (message.empty() ? "" : "; ") + notes;
  for (NamedCounter& c : node_counters(stats)) counters.push_back(std::move(c));
  const hsslam::tracker_status_t status = status_msg(r, counters, message);
  lcm_.publish(options_.channels.tracker_status, &status);
}

void TrackerNode::apply(Tracker& tracker, const MapCorrection& correction) {
  const CorrectionResult r = tracker.apply(correction);
  if (!r.message.empty()) correction_notes_ += (correction_notes_.empty() ? "" : "; ") + r.message;
  std::vector<NamedCounter> counters = tracker_counters(tracker.counters(), tracker.imu_counters());
  std::lock_guard<std::mutex> lock(mutex_);
  tracker_counters_ = std::move(counters);
}

std::string TrackerNode::status_notes() {
  int64_t drops = 0, bad = 0;
  std::string last_error;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    drops = stats_.frames_dropped;
    bad = stats_.bad_frame_messages + stats_.bad_imu_messages + stats_.bad_map_update_messages +
          stats_.bad_reloc_answer_messages + stats_.tracker_errors;
    last_error = last_error_;
  }
  std::string notes = std::move(correction_notes_);
  correction_notes_.clear();
  if (drops > reported_drops_)
    notes += (notes.empty() ? "" : "; ") + plural(drops - reported_drops_, "oldest frame") +
             " dropped: tracker queue full (total " + std::to_string(drops) + ")";
  if (bad > reported_bad_)
    notes += (notes.empty() ? "" : "; ") + plural(bad - reported_bad_, "bad input") +
             " ignored, last: " + last_error;
  reported_drops_ = drops;
  reported_bad_ = bad;
  return notes;
}

void TrackerNode::publish_heartbeat(int8_t state) {
  hsslam::heartbeat_t hb = heartbeat_header("hs-tracker", state);
  const InputQueueDepth depth = queue_.depth();
  hb.queue_names = {"frames", "imu_samples", "map_updates"};
  hb.queue_depths = {static_cast<int32_t>(depth.frames), static_cast<int32_t>(depth.imu_samples),
                     static_cast<int32_t>(depth.corrections)};
  hb.num_queues = static_cast<int32_t>(hb.queue_names.size());
  std::string last_error;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    hb.message =
        state_ ? std::string("tracker ") + to_string(*state_) : "waiting for a tracked frame";
    last_error = last_error_;
  }
  if (!last_error.empty()) hb.message += "; last bad input: " + last_error;
  add_counters(hb, counters());
  lcm_.publish(options_.channels.heartbeat, &hb);
}

}  // namespace hs
