#pragma once
// Where hs-imu's samples come from: a device it opens (and reopens after a loss), reads with a
// timeout and turns into samples on CLOCK_MONOTONIC, dropping and counting bad input. The node
// on top batches, publishes and reports; the backends are the Xsens serial protocol and Linux IIO.
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "common/core/types.h"

namespace hs {

struct ImuDriverOptions;

class ImuBackend {
 public:
  using Counters = std::vector<std::pair<std::string, int64_t>>;
  enum class ReadStatus { kData, kTimeout, kLost };

  virtual ~ImuBackend() = default;
  // Opens the device; throws std::exception saying why it cannot (missing, busy, mismatched).
  // Counters carry over reopenings.
  virtual void open() = 0;
  virtual void close() = 0;
  // Samples read within `timeout_ms`, appended to `samples`, in time order.
  virtual ReadStatus read(int timeout_ms, std::vector<ImuSample>* samples) = 0;

  virtual std::string device() const = 0;  // what open() opens, for messages
  // Bad input dropped so far (messages or samples), and what the last was.
  virtual int64_t bad_input() const = 0;
  virtual const std::string& last_error() const = 0;
  virtual Counters counters() const = 0;  // for HEARTBEAT and the exit summary
};

// The backend options.backend names ("xsens" or "iio").
std::unique_ptr<ImuBackend> make_imu_backend(const ImuDriverOptions& options);

}  // namespace hs
