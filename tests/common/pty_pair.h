#pragma once
// A pty pair, a real kernel tty for serial tests: the master plays the device, the slave's name
// is what the code under test opens. Close-on-exec, so a spawned process reaches it only by name
// (and sees a hangup when the test closes it, as with an unplugged device).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <pty.h>
#include <unistd.h>

#include <string>
#include <vector>

namespace hs::test {

struct PtyPair {
  int master = -1, slave = -1;
  std::string name;

  PtyPair() {
    char buf[128];
    EXPECT_EQ(::openpty(&master, &slave, buf, nullptr, nullptr), 0);
    name = buf;
    ::fcntl(master, F_SETFD, FD_CLOEXEC);
    ::fcntl(slave, F_SETFD, FD_CLOEXEC);
  }
  ~PtyPair() { close(); }
  PtyPair(const PtyPair&) = delete;
  PtyPair& operator=(const PtyPair&) = delete;

  void close() {
    if (master >= 0) ::close(master);
    if (slave >= 0) ::close(slave);
    master = slave = -1;
  }
  void send(const std::vector<uint8_t>& bytes) {
    EXPECT_EQ(::write(master, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
  }
};

}  // namespace hs::test
