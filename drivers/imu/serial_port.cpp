#include "drivers/imu/serial_port.h"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace hs {

unsigned baud_constant(int baud) {
  switch (baud) {
    case 9600:
      return B9600;
    case 19200:
      return B19200;
    case 38400:
      return B38400;
    case 57600:
      return B57600;
    case 115200:
      return B115200;
    case 230400:
      return B230400;
    case 460800:
      return B460800;
    case 921600:
      return B921600;
    case 2000000:
      return B2000000;
    case 4000000:
      return B4000000;
  }
  throw std::runtime_error("unsupported baud rate " + std::to_string(baud) +
                           " (9600 ... 921600, 2000000, 4000000)");
}

SerialPort::SerialPort(const std::string& device, int baud) : device_(device) {
  const unsigned speed = baud_constant(baud);
  fd_ = ::open(device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) {
    const int err = errno;
    throw std::runtime_error(device + ": cannot open: " + std::strerror(err) +
                             (err == EBUSY    ? " (another program has it)"
                              : err == EACCES ? " (add the user to the dialout group)"
                                              : ""));
  }
  termios tio{};
  if (::tcgetattr(fd_, &tio) != 0) {
    const std::string why = std::strerror(errno);
    ::close(fd_);
    throw std::runtime_error(device + ": not a serial device: " + why);
  }
  ::cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~(CSTOPB | PARENB | CRTSCTS);
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  ::cfsetispeed(&tio, speed);
  ::cfsetospeed(&tio, speed);
  if (::tcsetattr(fd_, TCSANOW, &tio) != 0) {
    const std::string why = std::strerror(errno);
    ::close(fd_);
    throw std::runtime_error(device + ": cannot set raw mode at " + std::to_string(baud) +
                             " baud: " + why);
  }
  ::tcflush(fd_, TCIFLUSH);  // bytes from before we listened have no usable receive time
}

SerialPort::~SerialPort() {
  if (fd_ >= 0) ::close(fd_);
}

SerialPort::ReadStatus SerialPort::read(uint8_t* buffer, size_t capacity, int timeout_ms,
                                        size_t* got) {
  *got = 0;
  pollfd p{fd_, POLLIN, 0};
  const int ready = ::poll(&p, 1, timeout_ms);
  if (ready < 0) return errno == EINTR ? ReadStatus::kTimeout : ReadStatus::kLost;
  if (ready == 0) return ReadStatus::kTimeout;
  if (p.revents & (POLLERR | POLLNVAL)) return ReadStatus::kLost;
  const ssize_t n = ::read(fd_, buffer, capacity);
  if (n > 0) {
    *got = static_cast<size_t>(n);
    return ReadStatus::kData;
  }
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) return ReadStatus::kTimeout;
  return ReadStatus::kLost;  // EOF (hangup) or EIO / ENODEV: the device is gone
}

}  // namespace hs
