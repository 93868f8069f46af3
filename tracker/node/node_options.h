#pragma once
// Options of the hs-tracker process around the tracker library (the `node:` section of the
// tracker config; config/euroc.yaml documents the keys).
#include <cstdint>

namespace hs {

struct NodeOptions {
  // Frames waiting for the tracker. When full the OLDEST is dropped (and counted): a robot wants
  // the newest pose, and a small queue bounds the latency. IMU samples are never dropped.
  int frame_queue_size = 2;
  int pose_imu_decimation = 1;                  // POSE_IMU for every Nth IMU sample
  int64_t heartbeat_period_ns = 1'000'000'000;  // HEARTBEAT period
};

}  // namespace hs
