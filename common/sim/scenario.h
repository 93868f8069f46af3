#pragma once
// A simulation scenario: world generator, trajectory, IMU and camera settings, events and seed,
// read strictly from YAML (config/sim/*.yaml). Unknown keys, wrong types, bad values and
// trajectories that leave the world or pass through an explicit box are InputErrors naming the
// file, line and key.
#include <cstdint>
#include <string>
#include <vector>

#include "common/calib/camera_calib.h"
#include "common/sim/imu_synth.h"
#include "common/sim/trajectory.h"
#include "common/sim/world_gen.h"

namespace hs::sim {

enum class BlackoutMode {
  kBlack,    // frames are rendered all black
  kMissing,  // frames are not produced at all
};

// Gain from t_ns on (1 before the first step). Event times are relative to the scenario start.
struct GainStep {
  int64_t t_ns = 0;
  double gain = 1.0;
};

struct ScenarioEvents {
  std::vector<GainStep> gain_steps;  // increasing times
  std::vector<TimeWindow> blackouts;
  BlackoutMode blackout_mode = BlackoutMode::kBlack;
  std::vector<TimeWindow> imu_gaps;
  // Informational: when the camera sees (almost) only textureless surfaces, for evaluations.
  std::vector<TimeWindow> textureless;

  double gain_at(int64_t t_rel_ns) const;
  bool in_blackout(int64_t t_rel_ns) const;
};

struct CameraSetup {
  StereoCalib calib = euroc_stereo_calib();  // EuRoC VI-sensor intrinsics and T_b_c
  double rate_hz = 20.0;
  double exposure_ms = 4.0;  // frames are stamped at mid-exposure
  bool noise = true;
  bool motion_blur = true;
  int texture_size = 1024;  // texels per texture tile side (power of two); 512 suits streets
};

struct Scenario {
  std::string name;
  std::string source;  // file it was read from
  uint64_t seed = 1;
  double duration_s = 30.0;
  int64_t start_time_ns = 1'700'000'000'000'000'000;  // time of the first IMU sample and frame
  WorldSpec world;
  TrajectoryOptions trajectory;
  ImuSynthOptions imu;  // gaps come from events.imu_gaps
  CameraSetup camera;
  ScenarioEvents events;
};

Scenario load_scenario(const std::string& path);

// Body positions every `step_s` over [0, duration_s] (and the end).
std::vector<Eigen::Vector3d> sample_path(const Trajectory& trajectory, double duration_s,
                                         double step_s);

}  // namespace hs::sim
