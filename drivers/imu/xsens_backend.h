#pragma once
// The Xsens MT serial protocol over a serial port (XsensStream on a SerialPort).
#include <memory>

#include "drivers/imu/imu_backend.h"
#include "drivers/imu/imu_driver_options.h"
#include "drivers/imu/serial_port.h"
#include "drivers/imu/xsens_stream.h"

namespace hs {

class XsensBackend : public ImuBackend {
 public:
  explicit XsensBackend(const ImuDriverOptions& options);
  void open() override;
  void close() override { port_.reset(); }
  ReadStatus read(int timeout_ms, std::vector<ImuSample>* samples) override;
  std::string device() const override;
  int64_t bad_input() const override;
  const std::string& last_error() const override { return stream_.last_error(); }
  Counters counters() const override;

 private:
  std::string device_;
  int baud_;
  XsensStream stream_;
  std::unique_ptr<SerialPort> port_;
  int64_t opens_ = 0;
  std::vector<uint8_t> buffer_ = std::vector<uint8_t>(4096);
};

}  // namespace hs
