// SerialPort on a real kernel tty: a pty pair (the master plays the device).
#include "drivers/imu/serial_port.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <stdexcept>

#include "tests/common/pty_pair.h"

namespace hs {
namespace {

using Pty = test::PtyPair;

TEST(SerialPort, ReadsWhatTheDeviceSendsAndTimesOutWhenSilent) {
  Pty pty;
  SerialPort port(pty.name, 921600);
  uint8_t buf[64];
  size_t got = 0;
  EXPECT_EQ(port.read(buf, sizeof buf, 20, &got), SerialPort::ReadStatus::kTimeout);
  const uint8_t sent[] = {0xFA, 0xFF, 0x36, 0x00, 0x0A, 0x0D};  // raw: no CR/LF translation
  ASSERT_EQ(::write(pty.master, sent, sizeof sent), static_cast<ssize_t>(sizeof sent));
  ASSERT_EQ(port.read(buf, sizeof buf, 1000, &got), SerialPort::ReadStatus::kData);
  ASSERT_EQ(got, sizeof sent);
  EXPECT_EQ(std::vector<uint8_t>(buf, buf + got), std::vector<uint8_t>(sent, sent + sizeof sent));
}

TEST(SerialPort, AHangupIsALostDevice) {
  Pty pty;
  SerialPort port(pty.name, 115200);
  pty.close();  // only the port's own descriptor is left
  uint8_t buf[16];
  size_t got = 0;
  EXPECT_EQ(port.read(buf, sizeof buf, 1000, &got), SerialPort::ReadStatus::kLost);
}

void expect_error(const std::function<void()>& f, const std::string& part) {
  try {
    f();
    ADD_FAILURE() << "expected an error with '" << part << "'";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(SerialPort, MissingDevicesNonTtysAndOddRatesAreClearErrors) {
  expect_error([] { SerialPort("/dev/hs-no-such-tty", 921600); },
               "/dev/hs-no-such-tty: cannot open: No such file or directory");
  char file[] = "/tmp/hs_not_a_tty_XXXXXX";
  const int fd = ::mkstemp(file);
  ::close(fd);
  expect_error([&] { SerialPort(file, 921600); }, "not a serial device");
  ::unlink(file);
  Pty pty;
  expect_error([&] { SerialPort(pty.name, 12345); }, "unsupported baud rate 12345");
}

}  // namespace
}  // namespace hs
