#include "drivers/imu/imu_driver_node.h"

#include <poll.h>

#include <cstdio>

#include "common/core/monotonic_clock.h"
#include "common/core/stop_signal.h"
#include "common/lcm/convert.h"
#include "common/lcm/process_loop.h"

namespace hs {
namespace {

constexpr int64_t kDegradedHoldNs = 10'000'000'000;  // bad input keeps HEARTBEAT DEGRADED this long

}  // namespace

ImuDriverNode::ImuDriverNode(lcm::LCM& lcm, ImuDriverOptions options)
    : lcm_(lcm), options_(std::move(options)), backend_(make_imu_backend(options_)) {}

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

void ImuDriverNode::publish_heartbeat(int64_t now_ns) {
  const bool degraded = problem_.recent(now_ns, kDegradedHoldNs);
  const int8_t state = !connected_ ? hsslam::heartbeat_t::ERROR
                       : degraded  ? hsslam::heartbeat_t::DEGRADED
                                   : hsslam::heartbeat_t::OK;
  hsslam::heartbeat_t hb = heartbeat_header("hs-imu", state);
  hb.message = connected_ ? "reading " + backend_->device() : problem_.text();
  if (connected_ && !problem_.empty()) hb.message += "; last problem: " + problem_.text();
  hb.queue_names = {"pending_samples"};
  hb.queue_depths = {static_cast<int32_t>(pending_.size())};
  hb.num_queues = 1;
  ImuBackend::Counters counters = {{"samples_published", stats_.samples_published},
                                   {"messages_published", stats_.messages_published}};
  const ImuBackend::Counters device = backend_->counters();
  counters.insert(counters.end(), device.begin(), device.end());
  counters.insert(counters.end(), {{"connects", stats_.connects},
                                   {"device_lost", stats_.device_lost},
                                   {"open_failures", stats_.open_failures}});
  add_counters(hb, counters);
  lcm_.publish(options_.channels.heartbeat, &hb);
}

void ImuDriverNode::run() {
  int64_t next_open = 0, next_heartbeat = 0;
  while (!stop_requested()) {
    int64_t now = monotonic_ns();
    if (!connected_ && now >= next_open) {
      try {
        backend_->open();
        ++stats_.connects;
        connected_ = true;
        problem_.clear();
        std::fprintf(stderr, "hs-imu: %s opened\n", backend_->device().c_str());
      } catch (const std::exception& e) {
        ++stats_.open_failures;
        problem_.set(std::string(e.what()) + "; retrying", now);
        next_open = now + options_.reconnect_period_ns;
      }
    }
    if (connected_) {
      const ImuBackend::ReadStatus status = backend_->read(50, &pending_);
      const int64_t read_ns = monotonic_ns();
      if (backend_->bad_input() != bad_input_seen_) {
        bad_input_seen_ = backend_->bad_input();
        problem_.set(backend_->last_error(), read_ns);
      }
      if (status == ImuBackend::ReadStatus::kData) {
        publish(false);
      } else if (status == ImuBackend::ReadStatus::kTimeout) {
        publish(true);  // the device paused: no sample waits for a batch to fill
      } else {
        publish(true);  // what was read before the loss is good
        backend_->close();
        connected_ = false;
        ++stats_.device_lost;
        problem_.set(backend_->device() + " lost (unplugged?); retrying", read_ns);
        next_open = read_ns + options_.reconnect_period_ns;
      }
    } else {
      ::poll(nullptr, 0, 50);
    }
    now = monotonic_ns();
    if (now >= next_heartbeat) {
      publish_heartbeat(now);
      next_heartbeat = now + options_.heartbeat_period_ns;
    }
  }
  publish(true);
}

}  // namespace hs
