#pragma once
// hs-logger's component: records the LCM channels the filter keeps into rotating log files
// (log_writer.h), optionally with PNG camera images, and reports on HEARTBEAT.
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <string>

#include "logger/channel_filter.h"
#include "logger/log_writer.h"
#include "logger/logger_options.h"

namespace hs {

struct LoggerCounters {
  int64_t received = 0;
  int64_t filtered_out = 0;
  int64_t png_recoded = 0;
  int64_t png_failed = 0;  // recorded as received
};

class LoggerNode {
 public:
  LoggerNode(lcm::LCM& lcm, const LoggerOptions& options);
  ~LoggerNode();
  LoggerNode(const LoggerNode&) = delete;
  LoggerNode& operator=(const LoggerNode&) = delete;

  void start();  // subscribes to every channel
  void poll();   // flushes / rotates when due, publishes HEARTBEAT when due
  void stop();   // unsubscribes, flushes and closes the file (its manifest is written)

  const LogWriterStatus& writer_status() const { return writer_.status(); }
  const LoggerCounters& counters() const { return counters_; }

 private:
  static void on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                         LoggerNode* self);
  void publish_heartbeat(int8_t state);

  lcm::LCM& lcm_;
  LoggerOptions options_;
  ChannelFilter filter_;
  LogWriter writer_;
  LoggerCounters counters_;
  lcm::Subscription* subscription_ = nullptr;
  int64_t next_heartbeat_ns_ = 0;
  std::string last_reported_message_;
};

}  // namespace hs
