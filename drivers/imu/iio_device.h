#pragma once
// An IMU behind a Linux IIO driver in buffered mode (SPI/I2C IMUs on embedded boards: ADIS16448
// like EuRoC's, BMI160, MPU-6050...): one device with accelerometer, gyroscope and the kernel's
// timestamp channel, or one of the two devices of an IMU whose accelerometer and gyroscope have
// drivers of their own (BMI088). Opening finds the device by name, checks that the configured
// channels are scan elements, enables exactly those, puts the timestamps on CLOCK_MONOTONIC, sets
// the trigger, rate and buffer length and starts the buffer; reads give samples in SI units ((raw +
// offset) * scale: m/s^2 and rad/s per the IIO ABI).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/core/types.h"
#include "drivers/imu/iio_scan.h"

namespace hs {

struct IioOptions {
  std::string device = "adis16448";  // the device's name attribute, or iio:deviceN
  std::string trigger;               // written to trigger/current_trigger; empty keeps the device's
  double sampling_frequency_hz = 0;  // 0 keeps the device's rate
  int buffer_length = 256;           // scans the kernel buffers
  std::array<std::string, 3> accel = {"in_accel_x", "in_accel_y", "in_accel_z"};
  std::array<std::string, 3> gyro = {"in_anglvel_x", "in_anglvel_y", "in_anglvel_z"};
  // A gyroscope that is a device of its own (empty: `device` has both); its trigger and rate.
  std::string gyro_device;
  std::string gyro_trigger;
  double gyro_sampling_frequency_hz = 0;
  double pair_max_gap_s = 0.02;  // longest accelerometer interval interpolated across
  std::string sysfs_root = "/sys/bus/iio/devices";  // another root only in tests
  std::string dev_root = "/dev";
};

// Which of the options' vectors a device delivers: kAccel is `device` when `gyro_device` is set,
// kGyro is `gyro_device` (with gyro_trigger and gyro_sampling_frequency_hz).
enum class IioPart { kBoth, kAccel, kGyro };

class IioDevice {
 public:
  // Throws InputError when the device's scan elements do not match the options (naming what it
  // has), std::runtime_error when it is missing, busy or refuses a setting.
  explicit IioDevice(const IioOptions& options, IioPart part = IioPart::kBoth);
  ~IioDevice();  // stops the buffer
  IioDevice(const IioDevice&) = delete;
  IioDevice& operator=(const IioDevice&) = delete;

  enum class ReadStatus { kData, kTimeout, kLost };
  // Whole scans read within `timeout_ms`, appended to `samples` with the kernel's timestamps
  // (the vectors the device does not deliver are zero).
  ReadStatus read(int timeout_ms, std::vector<ImuSample>* samples);
  int fd() const { return fd_; }  // for polling several devices

  const std::string& name() const { return name_; }  // "iio:device0 (adis16448)"
  size_t scan_bytes() const { return scan_bytes_; }

 private:
  struct Axis {
    size_t channel = 0;  // into channels_
    double scale = 1, offset = 0;
  };

  std::vector<std::string> scan_elements() const;
  // The configured channels and in_timestamp, checked against `available`.
  std::vector<std::string> wanted_channels(const IioOptions& o,
                                           const std::vector<std::string>& available) const;
  void set_trigger_and_rate(const std::string& sysfs_root, const std::string& trigger,
                            double rate_hz) const;
  // channels_, scan_bytes_, timestamp_ and the axes from the scan elements' index and type.
  void read_layout(const IioOptions& o, const std::vector<std::string>& wanted);

  std::string dir_, name_;
  int fd_ = -1;
  std::vector<IioScanChannel> channels_;
  bool has_accel_ = false, has_gyro_ = false;
  std::array<Axis, 3> accel_{}, gyro_{};
  size_t timestamp_ = 0;
  size_t scan_bytes_ = 0;
  std::vector<uint8_t> carry_;  // a partial scan from the last read
};

}  // namespace hs
