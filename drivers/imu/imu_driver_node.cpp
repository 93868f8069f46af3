#include "drivers/imu/imu_driver_node.h"

#include <poll.h>

#include <memory>

#include "common/core/monotonic_clock.h"
#include "common/core/stop_signal.h"
#include "common/lcm/convert.h"
#include "common/lcm/process_loop.h"
#include "drivers/imu/serial_port.h"

namespace hs {
namespace {

DeviceClockOptions xsens_clock(DeviceClockOptions clock, int baud) {
  clock.device_hz = kXsensSampleTimeHz;
  clock.counter_bits = 32;
  clock.transmission_ns = transmission_ns(kXsensMessageBytes, baud);
  return clock;
}

}  // namespace

ImuDriverNode::ImuDriverNode(lcm::LCM& lcm, ImuDriverOptions options)
    : lcm_(lcm),
      options_(std::move(options)),
      stream_(xsens_clock(options_.clock, options_.baud)) {}

void ImuDriverNode::publish(bool all) {
  const size_t batch = static_cast<size_t>(options_.batch_size);
  size_t done = 0;
  while (pending_.size() - done >= batch || (all && done < pending_.size())) {
    const size_t n = std::min(batch, pending_.size() - done);
    const std::vector<ImuSample> samples(pending_.begin() + static_cast<std::ptrdiff_t>(done),
                                         pending_.begin() + static_cast<std::ptrdiff_t>(done + n));
    const hsslam::imu_batch_t msg = imu_batch_to_msg(samples, seq_++);
    lcm_.publish(options_.channels.imu, &msg);
    stats_.samples_published += static_cast<int64_t>(n);
    ++stats_.messages_published;
    done += n;
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(done));
}

void ImuDriverNode::publish_heartbeat() {
  const int8_t state = !connected_         ? hsslam::heartbeat_t::ERROR
                       : !problem_.empty() ? hsslam::heartbeat_t::DEGRADED
                                           : hsslam::heartbeat_t::OK;
  hsslam::heartbeat_t hb = heartbeat_header("hs-imu", state);
  hb.message = connected_ ? "reading " + options_.device : problem_;
  if (connected_ && !problem_.empty()) hb.message += "; last problem: " + problem_;
  hb.queue_names = {"pending_samples"};
  hb.queue_depths = {static_cast<int32_t>(pending_.size())};
  hb.num_queues = 1;
  const XsensCounters p = stream_.protocol();
  const XsensStreamCounters& c = stream_.counters();
  const std::vector<std::pair<std::string, int64_t>> counters = {
      {"samples_published", stats_.samples_published},
      {"messages_published", stats_.messages_published},
      {"bad_checksum", p.bad_checksum},
      {"malformed", p.malformed},
      {"incomplete", p.incomplete},
      {"other_messages", p.other_messages},
      {"skipped_bytes", p.skipped_bytes},
      {"lost_samples", c.lost_samples},
      {"backwards_timestamps", c.backwards},
      {"connects", stats_.connects},
      {"device_lost", stats_.device_lost},
      {"open_failures", stats_.open_failures},
      {"clock_offset_us", stream_.clock().offset_ns() / 1000}};
  add_counters(hb, counters);
  lcm_.publish(options_.channels.heartbeat, &hb);
}

void ImuDriverNode::run() {
  std::unique_ptr<SerialPort> port;
  int64_t next_open = 0, next_heartbeat = 0;
  std::vector<uint8_t> buffer(4096);
  while (!stop_requested()) {
    int64_t now = monotonic_ns();
    if (!port && now >= next_open) {
      try {
        port = std::make_unique<SerialPort>(options_.device, options_.baud);
        if (stats_.connects++ > 0) stream_.reset();  // a new session of the device's counters
        connected_ = true;
        problem_.clear();
      } catch (const std::exception& e) {
        ++stats_.open_failures;
        problem_ = std::string(e.what()) + "; retrying";
        next_open = now + options_.reconnect_period_ns;
      }
    }
    if (port) {
      size_t got = 0;
      const SerialPort::ReadStatus status = port->read(buffer.data(), buffer.size(), 50, &got);
      const int64_t receive_ns = monotonic_ns();
      if (status == SerialPort::ReadStatus::kData) {
        const std::vector<ImuSample> samples = stream_.feed(buffer.data(), got, receive_ns);
        pending_.insert(pending_.end(), samples.begin(), samples.end());
        if (!stream_.last_error().empty()) problem_ = stream_.last_error();
        publish(false);
      } else if (status == SerialPort::ReadStatus::kTimeout) {
        publish(true);  // the device paused: no sample waits for a batch to fill
      } else {
        publish(true);  // what was read before the loss is good
        port.reset();
        connected_ = false;
        ++stats_.device_lost;
        problem_ = options_.device + " lost (unplugged?); retrying";
        next_open = receive_ns + options_.reconnect_period_ns;
      }
    } else {
      ::poll(nullptr, 0, 50);
    }
    now = monotonic_ns();
    if (now >= next_heartbeat) {
      publish_heartbeat();
      next_heartbeat = now + options_.heartbeat_period_ns;
    }
  }
  publish(true);
}

}  // namespace hs
