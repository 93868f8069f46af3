#pragma once
// The layout of an IIO buffer scan (Documentation/ABI/testing/sysfs-bus-iio, "scan_elements"):
// each enabled channel's bytes in scan-index order, each aligned to its own size, the scan padded
// to a multiple of the largest; a channel's type reads
// "[be|le]:[s|u]bits/storagebits[Xrepeat]>>shift".
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace hs {

struct IioScanType {
  bool big_endian = false;
  bool is_signed = false;
  int realbits = 0;
  int storagebits = 0;
  int repeat = 1;
  int shift = 0;

  size_t bytes() const { return static_cast<size_t>(storagebits / 8 * repeat); }
};

// Throws InputError saying what is wrong with `text` (as read from a *_type file).
IioScanType parse_iio_scan_type(const std::string& text);

struct IioScanChannel {
  std::string name;  // e.g. in_accel_x, in_timestamp
  int index = 0;     // scan_elements/<name>_index
  IioScanType type;
  size_t offset = 0;  // set by layout_iio_scan
};

// Sorts `channels` by index and sets their offsets; returns the bytes of one scan.
size_t layout_iio_scan(std::vector<IioScanChannel>& channels);

// The channel's (first) value in `scan`: shifted, masked to realbits and sign-extended.
int64_t decode_iio_value(const uint8_t* scan, const IioScanChannel& channel);

}  // namespace hs
