#pragma once
// Helpers for the tests that run the project's processes over udpm multicast on loopback.
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>

namespace hs::test {

// Polls `ready()` every 50 ms for up to `seconds`.
template <class Ready>
bool wait_for(Ready&& ready, int seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
  while (std::chrono::steady_clock::now() < deadline) {
    if (ready()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

// A port of the test's own, so parallel runs (and live processes on 7667) never cross-talk.
inline std::string private_udpm_url(int offset = 0) {
  return "udpm://239.255.76.67:" + std::to_string(20000 + (::getpid() + offset) % 40000) +
         "?ttl=0&recv_buf_size=16777216";
}

}  // namespace hs::test
