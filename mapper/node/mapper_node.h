#pragma once
// The mapper as an LCM component (the hs-mapper process). Subscribes to KEYFRAME (keyframe_t),
// runs the Mapper on each keyframe in a worker thread and publishes MAP_UPDATE (map_update_t)
// per keyframe and HEARTBEAT about once a period (backlog, counters). MAP_COMMAND (map_command_t)
// RELOC_REQUEST (reloc_request_t, a lost tracker's frame) is answered on RELOC_ANSWER from the
// atlas before the keyframes waiting (the tracker is waiting). MAP_COMMAND (map_command_t)
// SAVE writes the map between two keyframes and answers at once with a HEARTBEAT whose message
// says "save request <seq>: ..." (the file and its size, or why it failed).
//
// Threads: the receive thread (lcm.handle()) decodes and validates keyframes and queues them;
// it never waits for the mapper. The worker owns the Mapper, whose full BA after a loop runs in
// a thread of its own; the worker sends its correction as soon as it ends. The backlog is unbounded
// (every keyframe matters to the map) but measured: its depth is in every HEARTBEAT, its maximum in
// stats(). A restarted mapper starts from the keyframes that arrive; its update numbers start
// at 0 again, which the tracker recognises as a restart.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <lcm/lcm-cpp.hpp>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/config/channels.h"
#include "mapper/keyframe_from_msg.h"
#include "mapper/mapper.h"

namespace hs {

struct MapperNodeOptions {
  ChannelNames channels;
  int64_t heartbeat_period_ns = 1'000'000'000;
};

struct MapperNodeStats {
  int64_t keyframes_received = 0;
  int64_t bad_keyframe_messages = 0;
  int64_t keyframes_mapped = 0;
  int64_t updates_published = 0;
  int64_t commands_received = 0;
  int64_t bad_command_messages = 0;  // undecodable, unknown command or no path: answered, dropped
  int64_t reloc_requests_received = 0;
  int64_t bad_reloc_request_messages = 0;
  int64_t reloc_answers_published = 0;
  int64_t maps_saved = 0;
  int64_t map_save_failures = 0;
  size_t max_backlog = 0;   // keyframes waiting for the mapper, the most at any time
  double mapping_ms = 0.0;  // summed Mapper::add_keyframe wall time
};

class MapperNode {
 public:
  MapperNode(lcm::LCM& lcm, const StereoCalib& calib, const MapperOptions& options,
             const MapperNodeOptions& node_options);
  ~MapperNode();
  MapperNode(const MapperNode&) = delete;
  MapperNode& operator=(const MapperNode&) = delete;

  // Before start(): begin from a saved map. After stop(): the map to save.
  void load_map(const MapFile& map);
  MapFile map_file() const;

  void start();
  // Maps what is queued, stops the worker and publishes a STOPPING heartbeat. Idempotent.
  void stop();
  // Publishes HEARTBEAT when one is due. Call from the receive thread between lcm.handle()s.
  void poll();
  MapperNodeStats stats() const;

 private:
  static void on_keyframe(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                          MapperNode* self);
  void handle_keyframe(const void* data, size_t size, const std::string& channel);
  static void on_command(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                         MapperNode* self);
  void handle_command(const void* data, size_t size, const std::string& channel);
  static void on_reloc_request(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                               MapperNode* self);
  void handle_reloc_request(const void* data, size_t size, const std::string& channel);
  // Worker thread: where the atlas places a lost tracker's frame, published at once.
  void answer(const RelocRequest& request);
  // Worker thread: a SAVE request between two keyframes; answered by a heartbeat.
  void save_map(int64_t seq, const std::string& path);
  void run();
  // Sends the step's correction (if any) and takes its counters and message.
  void publish(const MapperStep& step, double ms, bool keyframe);
  void publish_heartbeat(int8_t state);

  lcm::LCM& lcm_;
  const MapperNodeOptions node_options_;
  Mapper mapper_;  // worker thread only (counters read under mutex_ after each keyframe)
  lcm::Subscription* subscription_ = nullptr;
  lcm::Subscription* command_subscription_ = nullptr;
  lcm::Subscription* reloc_subscription_ = nullptr;
  std::thread worker_;
  bool started_ = false;
  int64_t next_heartbeat_ns_ = 0;

  mutable std::mutex mutex_;  // guards everything below
  std::condition_variable ready_;
  std::deque<MapperKeyframe> queue_;
  std::deque<std::pair<int64_t, std::string>> save_requests_;  // (seq, path)
  std::deque<RelocRequest> reloc_requests_;
  bool closed_ = false;
  MapperNodeStats stats_;
  MapperCounters mapper_counters_;
  KeyframeGraphCounters graph_counters_;
  std::string last_message_;
};

}  // namespace hs
