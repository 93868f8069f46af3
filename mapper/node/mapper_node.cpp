#include "mapper/node/mapper_node.h"

#include <chrono>
#include <exception>
#include <filesystem>
#include <optional>
#include <stdexcept>

#include "common/core/monotonic_clock.h"
#include "common/lcm/convert.h"
#include "common/lcm/decode.h"
#include "common/lcm/process_loop.h"
#include "hsslam/heartbeat_t.hpp"
#include "hsslam/keyframe_t.hpp"
#include "hsslam/map_command_t.hpp"
#include "hsslam/map_update_t.hpp"
#include "hsslam/reloc_answer_t.hpp"
#include "hsslam/reloc_request_t.hpp"
#include "mapper/keyframe_from_msg.h"

namespace hs {

MapperNode::MapperNode(lcm::LCM& lcm, const StereoCalib& calib, const MapperOptions& options,
                       const MapperNodeOptions& node_options)
    : lcm_(lcm), node_options_(node_options), mapper_(calib, options) {
  // Plain-function handler: GCC 12 UBSan's vptr check breaks LCM's member-function dispatch.
  subscription_ =
      lcm_.subscribeFunction(node_options_.channels.keyframe, &MapperNode::on_keyframe, this);
  command_subscription_ =
      lcm_.subscribeFunction(node_options_.channels.map_command, &MapperNode::on_command, this);
  reloc_subscription_ = lcm_.subscribeFunction(node_options_.channels.reloc_request,
                                               &MapperNode::on_reloc_request, this);
}

MapperNode::~MapperNode() {
  stop();
  lcm_.unsubscribe(subscription_);
  lcm_.unsubscribe(command_subscription_);
  lcm_.unsubscribe(reloc_subscription_);
}

void MapperNode::load_map(const MapFile& map) {
  if (started_) throw std::logic_error("MapperNode::load_map after start()");
  mapper_.load(map);
}

MapFile MapperNode::map_file() const {
  if (worker_.joinable()) throw std::logic_error("MapperNode::map_file before stop()");
  return mapper_.map_file();
}

void MapperNode::start() {
  if (started_) return;
  started_ = true;
  worker_ = std::thread([this] { run(); });
  publish_heartbeat(hsslam::heartbeat_t::STARTING);
  next_heartbeat_ns_ = monotonic_ns() + node_options_.heartbeat_period_ns;
}

void MapperNode::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
  }
  ready_.notify_all();
  if (!worker_.joinable()) return;
  worker_.join();
  publish_heartbeat(hsslam::heartbeat_t::STOPPING);
  started_ = false;
}

void MapperNode::poll() {
  const int64_t now = monotonic_ns();
  if (!started_ || now < next_heartbeat_ns_) return;
  next_heartbeat_ns_ = now + node_options_.heartbeat_period_ns;
  publish_heartbeat(hsslam::heartbeat_t::OK);
}

MapperNodeStats MapperNode::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

void MapperNode::on_keyframe(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                             MapperNode* self) {
  self->handle_keyframe(rbuf->data, rbuf->data_size, channel);
}

void MapperNode::handle_keyframe(const void* data, size_t size, const std::string& channel) {
  // No exception may leave an LCM callback (it unwinds through C code).
  MapperKeyframe kf;
  std::string error;
  try {
    kf = keyframe_from_msg(decode_message<hsslam::keyframe_t>(data, size, channel), channel);
  } catch (const std::exception& e) {
    error = e.what();
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.keyframes_received;
    if (!error.empty()) {
      ++stats_.bad_keyframe_messages;
      last_message_ = error;
      return;
    }
    queue_.push_back(std::move(kf));
    stats_.max_backlog = std::max(stats_.max_backlog, queue_.size());
  }
  ready_.notify_one();
}

void MapperNode::on_command(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                            MapperNode* self) {
  self->handle_command(rbuf->data, rbuf->data_size, channel);
}

void MapperNode::handle_command(const void* data, size_t size, const std::string& channel) {
  hsslam::map_command_t msg;
  std::string error;
  try {
    msg = decode_message<hsslam::map_command_t>(data, size, channel);
    if (msg.command != hsslam::map_command_t::SAVE)
      error = "unknown command " + std::to_string(msg.command);
    else if (msg.path.empty())
      error = "SAVE without a path";
  } catch (const std::exception& e) {
    error = e.what();
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.commands_received;
    if (error.empty()) {
      save_requests_.emplace_back(msg.seq, msg.path);
    } else {
      ++stats_.bad_command_messages;
      last_message_ = "save request " + std::to_string(msg.seq) + " refused: " + error;
    }
  }
  if (error.empty())
    ready_.notify_one();
  else
    publish_heartbeat(hsslam::heartbeat_t::OK);
}

void MapperNode::on_reloc_request(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                                  MapperNode* self) {
  self->handle_reloc_request(rbuf->data, rbuf->data_size, channel);
}

void MapperNode::handle_reloc_request(const void* data, size_t size, const std::string& channel) {
  std::optional<RelocRequest> request;
  std::string error;
  try {
    request = reloc_request_from_msg(decode_message<hsslam::reloc_request_t>(data, size, channel),
                                     channel);
  } catch (const std::exception& e) {
    error = e.what();
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.reloc_requests_received;
    if (!request) {
      ++stats_.bad_reloc_request_messages;
      last_message_ = error;
      return;
    }
    reloc_requests_.push_back(std::move(*request));
  }
  ready_.notify_one();
}

void MapperNode::answer(const RelocRequest& request) {
  const RelocAnswer a = mapper_.relocalise(request.frame, request.seq, request.next_map_id);
  const hsslam::reloc_answer_t msg = reloc_answer_to_msg(a);
  lcm_.publish(node_options_.channels.reloc_answer, &msg);
  std::lock_guard<std::mutex> lock(mutex_);
  ++stats_.reloc_answers_published;
  mapper_counters_ = mapper_.counters();
  last_message_ = "reloc request " + std::to_string(a.seq) + ": " + a.message;
}

void MapperNode::save_map(int64_t seq, const std::string& path) {
  std::string message = "save request " + std::to_string(seq) + ": ";
  bool saved = false;
  try {
    const MapFile map = mapper_.map_file();
    write_map_file(path, map);
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(path, ec);
    message += "map saved to " + path + " (" + std::to_string(map.keyframes.size()) +
               " keyframes, " + std::to_string(ec ? 0 : bytes) + " bytes)";
    saved = true;
  } catch (const std::exception& e) {
    message += std::string("failed: ") + e.what();
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++(saved ? stats_.maps_saved : stats_.map_save_failures);
    last_message_ = message;
  }
  publish_heartbeat(hsslam::heartbeat_t::OK);
}

void MapperNode::run() {
  for (;;) {
    std::optional<MapperKeyframe> kf;
    std::optional<std::pair<int64_t, std::string>> save;
    std::optional<RelocRequest> request;
    bool closing = false;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      const auto woken = [&] {
        return closed_ || !queue_.empty() || !save_requests_.empty() || !reloc_requests_.empty();
      };
      // A full BA running in the background lands as soon as it ends, keyframes or not (the
      // vehicle may be standing still).
      if (mapper_.full_ba_running())
        ready_.wait_for(lock, std::chrono::milliseconds(50), woken);
      else
        ready_.wait(lock, woken);
      if (!reloc_requests_.empty()) {
        request = std::move(reloc_requests_.front());
        reloc_requests_.pop_front();
      } else if (!save_requests_.empty()) {
        save = std::move(save_requests_.front());
        save_requests_.pop_front();
      } else if (!queue_.empty()) {
        kf = std::move(queue_.front());
        queue_.pop_front();
      } else {
        closing = closed_;
      }
    }
    if (request) {
      answer(*request);
      continue;
    }
    if (save) {
      save_map(save->first, save->second);
      continue;
    }
    if (!kf) {
      // Between keyframes, and at the end: the map saved after stop() has the full BA in it.
      publish(mapper_.finish_full_ba(closing), 0.0, false);
      if (closing) return;
      continue;
    }
    const auto start = std::chrono::steady_clock::now();
    MapperStep step = mapper_.add_keyframe(std::move(*kf));
    publish(
        step,
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count(),
        true);
  }
}

void MapperNode::publish(const MapperStep& step, double ms, bool keyframe) {
  if (step.correction) {
    const hsslam::map_update_t msg = map_update_to_msg(*step.correction);
    lcm_.publish(node_options_.channels.map_update, &msg);
  }
  std::lock_guard<std::mutex> lock(mutex_);
  stats_.keyframes_mapped += keyframe;
  stats_.updates_published += step.correction.has_value();
  stats_.mapping_ms += ms;
  mapper_counters_ = mapper_.counters();
  graph_counters_ = mapper_.graph().counters();
  if (!step.message.empty()) last_message_ = step.message;
}

void MapperNode::publish_heartbeat(int8_t state) {
  hsslam::heartbeat_t hb = heartbeat_header("hs-mapper", state);
  std::lock_guard<std::mutex> lock(mutex_);
  hb.message = last_message_;
  hb.queue_names = {"keyframes"};
  hb.queue_depths = {static_cast<int32_t>(queue_.size())};
  hb.num_queues = 1;
  const MapperNodeStats& s = stats_;
  const MapperCounters& m = mapper_counters_;
  const KeyframeGraphCounters& g = graph_counters_;
  const std::vector<std::pair<std::string, int64_t>> counters = {
      {"keyframes_received", s.keyframes_received},
      {"bad_keyframe_messages", s.bad_keyframe_messages},
      {"keyframes_mapped", s.keyframes_mapped},
      {"updates_published", s.updates_published},
      {"commands_received", s.commands_received},
      {"bad_command_messages", s.bad_command_messages},
      {"reloc_requests_received", s.reloc_requests_received},
      {"bad_reloc_request_messages", s.bad_reloc_request_messages},
      {"reloc_answers_published", s.reloc_answers_published},
      {"relocalisations", m.relocalisations},
      {"maps_saved", s.maps_saved},
      {"map_save_failures", s.map_save_failures},
      {"max_backlog", static_cast<int64_t>(s.max_backlog)},
      {"local_ba_runs", m.local_ba_runs},
      {"new_points", m.new_points},
      {"culled_keyframes", m.culled_keyframes},
      {"removed_points", m.removed_points},
      {"imu_factors_skipped", m.imu_factors_skipped},
      {"loops_detected", m.loops_detected},
      {"loops_closed", m.loops_closed},
      {"maps_merged", m.maps_merged},
      {"full_bas", m.full_bas},
      {"points_fused", m.points_fused},
      {"points_fused_as_ties", m.points_fused_as_ties},
      {"places_implausible", m.places_implausible},
      {"duplicate_keyframes", g.duplicates},
      {"out_of_order_keyframes", g.out_of_order},
      {"missing_previous_keyframes", g.missing_prev},
      {"map_changes", g.map_changes}};
  add_counters(hb, counters);
  lcm_.publish(node_options_.channels.heartbeat, &hb);
}

}  // namespace hs
