#include "common/lcm/decode.h"

namespace hs {

int64_t message_fingerprint(const void* data, size_t size) {
  if (size < 8) return 0;
  const auto* b = static_cast<const uint8_t*>(data);
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | b[i];  // big-endian on the wire
  return static_cast<int64_t>(v);
}

}  // namespace hs
