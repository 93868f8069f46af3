#pragma once
// A serial device (a USB-serial adapter, a UART, a pty in tests) in raw 8N1 mode at a given baud
// rate. Opening fails with the reason (missing, busy, not a tty, unsupported rate); reads wait
// with a timeout and report a lost device (unplugged: EOF, EIO or ENODEV) as such.
#include <cstddef>
#include <cstdint>
#include <string>

namespace hs {

class SerialPort {
 public:
  // Throws std::runtime_error naming the device and why.
  SerialPort(const std::string& device, int baud);
  ~SerialPort();
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  enum class ReadStatus { kData, kTimeout, kLost };
  // Up to `capacity` bytes, waiting at most `timeout_ms`.
  ReadStatus read(uint8_t* buffer, size_t capacity, int timeout_ms, size_t* got);
  const std::string& device() const { return device_; }

 private:
  std::string device_;
  int fd_ = -1;
};

// The termios speed constant of a baud rate; throws std::runtime_error for an unsupported one.
unsigned baud_constant(int baud);

}  // namespace hs
