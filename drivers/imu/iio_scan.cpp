#include "drivers/imu/iio_scan.h"

#include <algorithm>
#include <cstdio>

#include "common/core/error.h"

namespace hs {

IioScanType parse_iio_scan_type(const std::string& text) {
  IioScanType t;
  char endian[3] = {}, sign = 0;
  int consumed = 0;
  std::string s = text;
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  const bool repeated = s.find('X') != std::string::npos;
  const int fields = repeated
                         ? std::sscanf(s.c_str(), "%2[bl]e:%c%d/%dX%d>>%d%n", endian, &sign,
                                       &t.realbits, &t.storagebits, &t.repeat, &t.shift, &consumed)
                         : std::sscanf(s.c_str(), "%2[bl]e:%c%d/%d>>%d%n", endian, &sign,
                                       &t.realbits, &t.storagebits, &t.shift, &consumed);
  if (fields != (repeated ? 6 : 5) || static_cast<size_t>(consumed) != s.size())
    throw InputError("IIO scan type '" + s + "' is not [be|le]:[s|u]bits/storagebits>>shift");
  t.big_endian = endian[0] == 'b';
  if (sign != 's' && sign != 'u' && sign != 'S' && sign != 'U')
    throw InputError("IIO scan type '" + s + "': sign must be s or u");
  t.is_signed = sign == 's' || sign == 'S';
  if (t.storagebits != 8 && t.storagebits != 16 && t.storagebits != 32 && t.storagebits != 64)
    throw InputError("IIO scan type '" + s + "': storage of " + std::to_string(t.storagebits) +
                     " bits (8, 16, 32 or 64 expected)");
  if (t.realbits < 1 || t.shift < 0 || t.realbits + t.shift > t.storagebits || t.repeat < 1)
    throw InputError("IIO scan type '" + s + "': " + std::to_string(t.realbits) + " bits >> " +
                     std::to_string(t.shift) + " do not fit " + std::to_string(t.storagebits));
  return t;
}

size_t layout_iio_scan(std::vector<IioScanChannel>& channels) {
  std::sort(channels.begin(), channels.end(),
            [](const IioScanChannel& a, const IioScanChannel& b) { return a.index < b.index; });
  size_t bytes = 0, largest = 1;
  for (IioScanChannel& c : channels) {
    const size_t size = c.type.bytes();
    bytes = (bytes + size - 1) / size * size;
    c.offset = bytes;
    bytes += size;
    largest = std::max(largest, size);
  }
  return (bytes + largest - 1) / largest * largest;
}

int64_t decode_iio_value(const uint8_t* scan, const IioScanChannel& channel) {
  const IioScanType& t = channel.type;
  const int n = t.storagebits / 8;
  const uint8_t* p = scan + channel.offset;
  uint64_t raw = 0;
  for (int i = 0; i < n; ++i) {
    const uint8_t byte = t.big_endian ? p[i] : p[n - 1 - i];
    raw = raw << 8 | byte;
  }
  raw >>= t.shift;
  if (t.realbits < 64) {
    raw &= (uint64_t{1} << t.realbits) - 1;
    if (t.is_signed && (raw >> (t.realbits - 1)) & 1) raw |= ~uint64_t{0} << t.realbits;
  }
  return static_cast<int64_t>(raw);
}

}  // namespace hs
