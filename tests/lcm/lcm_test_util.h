#pragma once
// Encoding LCM messages to their wire bytes, and collecting what is published, in tests.
#include <gtest/gtest.h>

#include <cstdint>
#include <exception>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "common/lcm/decode.h"

namespace hs::test {

template <class Msg>
std::vector<uint8_t> encode_bytes(const Msg& msg) {
  std::vector<uint8_t> bytes(static_cast<size_t>(msg.getEncodedSize()));
  msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

// LCM handler: every message on the channel, decoded (a message that does not decode fails the
// test).
template <class Msg>
void collect(const lcm::ReceiveBuffer* rbuf, const std::string& channel, std::vector<Msg>* out) {
  try {
    out->push_back(decode_message<Msg>(rbuf->data, rbuf->data_size, channel));
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
  }
}

}  // namespace hs::test
