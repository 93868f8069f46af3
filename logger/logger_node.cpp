#include "logger/logger_node.h"

#include <cstdio>

#include "common/core/monotonic_clock.h"
#include "common/lcm/process_loop.h"
#include "logger/png_recode.h"

namespace hs {
namespace {

constexpr int kReceiveQueueMessages = 2000;

}  // namespace

LoggerNode::LoggerNode(lcm::LCM& lcm, const LoggerOptions& options)
    : lcm_(lcm),
      options_(options),
      filter_(options.include, options.exclude),
      writer_(options.writer) {}

LoggerNode::~LoggerNode() {
  stop();
}

void LoggerNode::start() {
  subscription_ = lcm_.subscribeFunction(".*", &LoggerNode::on_message, this);
  // LCM queues 30 messages per subscription and silently drops beyond: at ~650 messages/s
  // (IMU, POSE_IMU, ground truth...) a 50 ms disk flush would lose some. 2000 is 3 s of that.
  subscription_->setQueueCapacity(kReceiveQueueMessages);
  publish_heartbeat(hsslam::heartbeat_t::STARTING);
  next_heartbeat_ns_ = monotonic_ns() + options_.heartbeat_period_ns;
}

void LoggerNode::on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                            LoggerNode* self) {
  ++self->counters_.received;
  if (!self->filter_.keep(channel)) {
    ++self->counters_.filtered_out;
    return;
  }
  const auto* bytes = static_cast<const uint8_t*>(rbuf->data);
  const int64_t now_ns = monotonic_ns();
  if (self->options_.png_images && channel == self->options_.channels.cam_stereo) {
    std::vector<uint8_t> data(bytes, bytes + rbuf->data_size);
    std::string error;
    if (recode_stereo_png(&data, &error)) {
      ++self->counters_.png_recoded;
      self->writer_.write(channel, rbuf->recv_utime, data.data(), data.size(), now_ns);
      return;
    }
    if (self->counters_.png_failed++ == 0)
      std::fprintf(stderr, "hs-logger: %s message not recompressed (%s): recorded as received\n",
                   channel.c_str(), error.c_str());
  }
  self->writer_.write(channel, rbuf->recv_utime, bytes, rbuf->data_size, now_ns);
}

void LoggerNode::poll() {
  const int64_t now_ns = monotonic_ns();
  writer_.poll(now_ns);
  const LogWriterStatus& s = writer_.status();
  if (s.message != last_reported_message_) {
    last_reported_message_ = s.message;
    if (!s.message.empty()) std::fprintf(stderr, "hs-logger: %s\n", s.message.c_str());
  }
  if (now_ns < next_heartbeat_ns_) return;
  next_heartbeat_ns_ = now_ns + options_.heartbeat_period_ns;
  publish_heartbeat(s.recording ? hsslam::heartbeat_t::OK : hsslam::heartbeat_t::DEGRADED);
}

void LoggerNode::stop() {
  if (subscription_) {
    lcm_.unsubscribe(subscription_);
    subscription_ = nullptr;
    publish_heartbeat(hsslam::heartbeat_t::STOPPING);
  }
  writer_.close();
}

void LoggerNode::publish_heartbeat(int8_t state) {
  const LogWriterStatus& s = writer_.status();
  hsslam::heartbeat_t hb = heartbeat_header("hs-logger", state);
  hb.message = s.recording ? (s.current_file.empty() ? "waiting for messages"
                                                     : "recording " + s.current_file)
                           : s.message;
  hb.queue_names = {"buffer_kb"};
  hb.queue_depths = {static_cast<int32_t>(s.buffered_bytes >> 10)};
  hb.num_queues = 1;
  const std::pair<const char*, int64_t> counters[] = {
      {"received", counters_.received},
      {"filtered_out", counters_.filtered_out},
      {"events_written", s.events_written},
      {"events_dropped", s.events_dropped},
      {"bytes_written", s.bytes_written},
      {"files_closed", s.files_closed},
      {"files_deleted", s.files_deleted},
      {"write_errors", s.write_errors},
      {"png_recoded", counters_.png_recoded},
      {"png_failed", counters_.png_failed},
      {"free_mb", s.free_bytes < 0 ? -1 : s.free_bytes >> 20}};
  add_counters(hb, counters);
  lcm_.publish(options_.channels.heartbeat, &hb);
}

}  // namespace hs
