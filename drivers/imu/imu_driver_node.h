#pragma once
// hs-imu's work: reads samples from the backend (Xsens serial or Linux IIO, on CLOCK_MONOTONIC)
// and publishes them on IMU in batches of batch_size (fewer when the device pauses for a read
// timeout, so no sample waits for a batch to fill), with HEARTBEAT (state, counters, the last
// problem: DEGRADED while bad input was dropped within the last 10 s). A device that cannot be
// opened or is lost (unplugged) is said so and retried every reconnect period; it recovers
// without a restart and nothing is published from a device that is not there.
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>
#include <vector>

#include "common/core/problem_report.h"
#include "drivers/imu/imu_backend.h"
#include "drivers/imu/imu_driver_options.h"

namespace hs {

struct ImuDriverStats {
  int64_t samples_published = 0;
  int64_t messages_published = 0;
  int64_t connects = 0;     // successful opens
  int64_t device_lost = 0;  // read failures of an open device
  int64_t open_failures = 0;
};

class ImuDriverNode {
 public:
  ImuDriverNode(lcm::LCM& lcm, ImuDriverOptions options);
  // Until stop_requested() (install_stop_signals() first).
  void run();
  const ImuDriverStats& stats() const { return stats_; }
  const ImuBackend& backend() const { return *backend_; }

 private:
  void publish(bool all);
  void publish_heartbeat(int64_t now_ns);

  lcm::LCM& lcm_;
  ImuDriverOptions options_;
  std::unique_ptr<ImuBackend> backend_;
  std::vector<ImuSample> pending_;
  int64_t seq_ = 0;
  bool connected_ = false;
  ProblemReport problem_{"hs-imu"};  // why it is not reading, or the last bad input
  int64_t bad_input_seen_ = 0;
  ImuDriverStats stats_;
};

}  // namespace hs
