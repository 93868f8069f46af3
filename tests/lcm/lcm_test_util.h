#pragma once
// Encoding LCM messages to their wire bytes in tests.
#include <cstdint>
#include <vector>

namespace hs::test {

template <class Msg>
std::vector<uint8_t> encode_bytes(const Msg& msg) {
  std::vector<uint8_t> bytes(static_cast<size_t>(msg.getEncodedSize()));
  msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

}  // namespace hs::test
