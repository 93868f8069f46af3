#pragma once
// Checked decoding of raw LCM bytes: wrong type, truncation, trailing bytes or absurd array
// sizes become an InputError naming the channel, never a crash.
#include <climits>
#include <cstdint>
#include <exception>
#include <string>

#include "common/core/error.h"

namespace hs {

// The 8-byte type fingerprint every LCM message starts with; 0 if `size` < 8.
int64_t message_fingerprint(const void* data, size_t size);

template <class Msg>
Msg decode_message(const void* data, size_t size, const std::string& channel) {
  const std::string type = Msg::getTypeName();
  if (size < 8 || size > INT_MAX)
    throw InputError(channel, type + ": message of " + std::to_string(size) + " bytes");
  if (message_fingerprint(data, size) != Msg::getHash())
    throw InputError(channel, "message is not a " + type + " (fingerprint mismatch)");
  Msg msg;
  int used = -1;
  try {
    used = msg.decode(data, 0, static_cast<int>(size));
  } catch (const std::exception& e) {  // e.g. a negative array length makes vector::resize throw
    throw InputError(channel, type + ": corrupt array length (" + e.what() + ")");
  }
  if (used < 0)
    throw InputError(channel, type + ": truncated or corrupt (" + std::to_string(size) + " bytes)");
  if (static_cast<size_t>(used) != size)
    throw InputError(channel, type + ": " + std::to_string(size - used) + " trailing bytes");
  return msg;
}

}  // namespace hs
