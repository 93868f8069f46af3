#pragma once
// Timestamped body poses in a world frame, read from TUM or EuRoC ground-truth files and
// written as TUM.
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace hs {

struct StampedPose {
  int64_t t_ns = 0;
  Eigen::Isometry3d T_w_b = Eigen::Isometry3d::Identity();
};

struct Trajectory {
  std::vector<StampedPose> poses;  // strictly increasing t_ns
};

enum class TrajectoryFormat {
  kAuto,   // EuRoC if the first data line contains ',', TUM otherwise
  kTum,    // "t[s] x y z qx qy qz qw", whitespace separated
  kEuroc,  // "t_ns,px,py,pz,qw,qx,qy,qz[,...]" (state_groundtruth_estimate0/data.csv)
};

// A quaternion whose norm differs from 1 by more than this is rejected as corrupt; smaller
// deviations (rounding in text files) are normalised away.
constexpr double kQuatNormTolerance = 1e-3;

// Throws InputError naming file:line on malformed lines, non-unit quaternions and
// non-increasing (including duplicate) timestamps, and naming the file when it has no poses.
Trajectory load_trajectory(const std::string& path,
                           TrajectoryFormat format = TrajectoryFormat::kAuto);

// Writes TUM format with exact nanosecond timestamps, atomically.
void save_tum(const std::string& path, const Trajectory& trajectory);

// The format kAuto resolves to for this file (reads up to its first data line).
TrajectoryFormat detect_trajectory_format(const std::string& path);

// Parses "auto", "tum" or "euroc"; throws InputError otherwise.
TrajectoryFormat parse_trajectory_format(const std::string& name);
const char* format_name(TrajectoryFormat format);

}  // namespace hs
