#pragma once
// All options of hs-imu, from one YAML config (config/imu.yaml documents every key).
#include <cstdint>
#include <string>

#include "common/config/channels.h"
#include "drivers/imu/device_clock.h"
#include "drivers/imu/iio_device.h"

namespace hs {

struct ImuDriverOptions {
  std::string backend = "xsens";  // xsens: the Xsens MT serial protocol (MTData2); iio: Linux IIO
  std::string device = "/dev/ttyUSB0";  // xsens
  int baud = 921600;                    // xsens
  IioOptions iio;
  int batch_size = 4;  // samples per IMU message (200 Hz: 50 messages/s)
  int64_t reconnect_period_ns = 1'000'000'000;
  DeviceClockOptions clock;  // window_ns from config; the rest set by the backend
  int64_t heartbeat_period_ns = 1'000'000'000;
  ChannelNames channels;
};

// Unknown keys, wrong types or bad values: InputError with file:line.
ImuDriverOptions load_imu_driver_options(const std::string& path);

// Bytes of the MTData2 message hs-imu expects (counter, time, acceleration, rate of turn): its
// time on the wire at `baud` is the delay even the fastest sample has.
constexpr int kXsensMessageBytes = 47;
int64_t transmission_ns(int message_bytes, int baud);

}  // namespace hs
