#pragma once
// Parsers for the EuRoC ASL data.csv files. Every row must have exactly the EuRoC columns and
// timestamps must strictly increase; anything else is an InputError naming file:line.
#include <cstdint>
#include <string>
#include <vector>

#include "common/core/types.h"

namespace hs {

struct ImageEntry {
  int64_t t_ns = 0;
  std::string path;  // <cam>/data/<filename>
  long line = 0;     // row in <cam>/data.csv
};

// <cam_dir>/data.csv: timestamp, filename.
std::vector<ImageEntry> read_camera_csv(const std::string& cam_dir);
// imu0/data.csv: timestamp, gyro xyz [rad/s], accel xyz [m/s^2].
std::vector<ImuSample> read_imu_csv(const std::string& path);
// state_groundtruth_estimate0/data.csv: timestamp, p, q (w x y z), v, gyro bias, accel bias.
std::vector<NavState> read_ground_truth_csv(const std::string& path);

}  // namespace hs
