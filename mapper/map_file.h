#pragma once
// The mapper's map on disk (issue 7, hs-mapper --save-map / --load-map): keyframes with their
// keypoints, descriptors, states and IMU, the positions of the points they observe, the loops
// closed so far and gravity. Binary, little-endian, versioned and checksummed:
//   "HSSLAMAP" | u32 version | u64 payload bytes | u32 CRC-32 of the payload | payload
// A file that is not one, of another version, truncated or corrupt is refused with an
// InputError naming the file and what is wrong; nothing of it is used.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "mapper/loop_detector.h"
#include "mapper/mapper_keyframe.h"

namespace hs {

constexpr uint32_t kMapFileVersion = 2;  // 2: keypoints say whether they were detected

// A loaded map's ids are moved up to here, out of the way of the running tracker's, which start
// from 0 again (ids already there stay: a map saved after loading one loads the same way).
constexpr int64_t kLoadedKeyframeIdBase = int64_t{1} << 48;
constexpr int64_t kLoadedPointIdBase = int64_t{1} << 56;  // tracker points (< 2^60) only
constexpr int32_t kLoadedMapIdBase = int32_t{1} << 24;
inline bool loaded_keyframe(int64_t id) {
  return id >= kLoadedKeyframeIdBase;
}

struct MapFile {
  // In id order; point_positions holds every observed point (the store's positions).
  std::vector<MapperKeyframe> keyframes;
  std::vector<LoopFound> loops;  // closed
  Eigen::Vector3d g_w = Eigen::Vector3d::Zero();
};

// Atomic: a crash while writing leaves the old file.
void write_map_file(const std::string& path, const MapFile& map);
MapFile read_map_file(const std::string& path);

// CRC-32 (IEEE 802.3, as zlib's crc32).
uint32_t crc32(const uint8_t* data, size_t size);

}  // namespace hs
