#pragma once
// Smooth analytic body trajectories with exact derivatives. The path is a quintic B-spline
// through control points resampled evenly along a waypoint polyline (so the cruise speed is set
// directly), traversed with a smooth speed profile s(t) (hold, ramp up, cruise, ramp down, hold).
// Orientation: a vehicle frame (x forward, y left, z up) with yaw, pitch, roll (ZYX), turned into
// the body (IMU) frame by a fixed mount rotation.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "common/sim/trajectory_spline.h"

namespace hs::sim {

constexpr double kGravityMps2 = 9.81;  // world gravity is (0, 0, -kGravityMps2)

enum class YawMode {
  kHeading,    // yaw follows the path tangent: no sideways slip (closed paths only)
  kKeyframes,  // yaw from keyframes spaced yaw_knot_s apart in path time
};

// The EuRoC VI-sensor mount: body x up, y right, z forward (its cameras look along body z).
Eigen::Matrix3d euroc_R_vehicle_body();

struct TrajectoryOptions {
  std::vector<Eigen::Vector3d> waypoints;  // world polyline; corners get rounded
  bool closed = false;                     // closed loops are periodic
  double speed_mps = 1.0;                  // cruise speed along the polyline
  double knot_s = 0.5;                     // control points every speed_mps * knot_s metres
  int laps = 1;                            // closed paths: times round the loop
  double start_hold_s = 1.0;               // at rest before moving
  double ramp_s = 2.0;                     // speed-up and slow-down time
  YawMode yaw_mode = YawMode::kHeading;
  std::vector<double> yaw_deg;  // kKeyframes: unwrapped yaw keyframes (vehicle x from world x)
  double yaw_knot_s = 1.0;
  // Pitch/roll from acceleration: 1 tilts the vehicle z axis onto the specific force (a
  // quadrotor's thrust), a small negative gain mimics a car's body roll and squat, 0 keeps level.
  double tilt_gain = 0.0;
  Eigen::Matrix3d R_vehicle_body = euroc_R_vehicle_body();
};

// Exact kinematics of the body frame at one instant.
struct BodyKinematics {
  Eigen::Vector3d p_w_b = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_w = Eigen::Vector3d::Zero();
  Eigen::Vector3d a_w = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_w_b = Eigen::Quaterniond::Identity();
  Eigen::Vector3d omega_b = Eigen::Vector3d::Zero();  // body angular velocity, body frame
};

class Trajectory {
 public:
  // Throws std::invalid_argument for unusable options (validated with file:line by the scenario).
  explicit Trajectory(const TrajectoryOptions& options);

  BodyKinematics at(double t_s) const;
  double motion_end_s() const;   // time when the body is back at rest
  double path_length_s() const;  // path time of one loop (closed) or the whole path (open)

 private:
  struct Warp {
    double s = 0, ds = 0, dds = 0, ddds = 0;  // path time and its time derivatives
  };
  Warp warp(double t_s) const;

  TrajectoryOptions opt_;
  QuinticSpline<3> path_;
  std::optional<QuinticSpline<1>> yaw_;
  double s_end_ = 0.0;   // path time where motion stops
  double ramp_s_ = 0.0;  // effective ramp (shortened for very short paths)
};

// Control points every `spacing` metres along a polyline (closed: wraps, without repeating the
// first point). A single waypoint yields itself.
std::vector<Eigen::Vector3d> resample_polyline(const std::vector<Eigen::Vector3d>& waypoints,
                                               double spacing, bool closed);

}  // namespace hs::sim
