#include "common/sim/scenario.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "common/config/config_section.h"

namespace hs::sim {
namespace {

constexpr double kPathCheckStepS = 0.02;

// Reads a flat list of numbers whose length is a multiple of `group` (e.g. 3 per waypoint).
std::vector<double> read_groups(ConfigSection& s, const std::string& key, size_t group,
                                bool required) {
  std::vector<double> values;
  const bool present = s.read(key, values);
  if (required && (!present || values.empty()))
    s.fail(key, "needs at least one group of " + std::to_string(group) + " numbers");
  if (values.size() % group != 0)
    s.fail(key, "needs groups of " + std::to_string(group) + " numbers, got " +
                    std::to_string(values.size()) + " numbers");
  return values;
}

void read_vec3(ConfigSection& s, const std::string& key, Eigen::Vector3d& out) {
  std::vector<double> v;
  if (!s.read(key, v)) return;
  if (v.size() != 3) s.fail(key, "needs 3 numbers");
  out = Eigen::Vector3d(v[0], v[1], v[2]);
}

void read_vec2(ConfigSection& s, const std::string& key, Eigen::Vector2d& out) {
  std::vector<double> v;
  if (!s.read(key, v)) return;
  if (v.size() != 2) s.fail(key, "needs 2 numbers");
  out = Eigen::Vector2d(v[0], v[1]);
}

void read_positive(ConfigSection& s, const std::string& key, double& out) {
  if (s.read(key, out) && !(out > 0.0)) s.fail(key, "must be positive");
}

void read_non_negative(ConfigSection& s, const std::string& key, double& out) {
  if (s.read(key, out) && out < 0.0) s.fail(key, "must not be negative");
}

// [start, end] pairs in seconds, inside the scenario.
std::vector<TimeWindow> read_windows(ConfigSection& s, const std::string& key, double duration_s) {
  const std::vector<double> v = read_groups(s, key, 2, false);
  std::vector<TimeWindow> windows;
  for (size_t i = 0; i < v.size(); i += 2) {
    if (!(v[i] >= 0.0 && v[i] < v[i + 1] && v[i + 1] <= duration_s))
      s.fail(key, "windows need 0 <= start < end <= duration_s");
    windows.push_back({s_to_ns(v[i]), s_to_ns(v[i + 1])});
  }
  return windows;
}

std::string format_point(const Eigen::Vector3d& p) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), "(%.2f, %.2f, %.2f)", p.x(), p.y(), p.z());
  return buf;
}

void read_world(ConfigSection& s, WorldSpec& w) {
  const std::string type = s.require<std::string>("type");
  if (type == "room") {
    w.type = WorldType::kRoom;
  } else if (type == "street") {
    w.type = WorldType::kStreet;
  } else {
    s.fail("type", "must be 'room' or 'street', got '" + type + "'");
  }
  read_vec3(s, "room_size_m", w.room_size_m);
  if (!(w.room_size_m.minCoeff() > 0.0)) s.fail("room_size_m", "sizes must be positive");
  if (s.read("furniture", w.furniture) && w.furniture < 0) s.fail("furniture", "must be >= 0");
  read_vec2(s, "street_min_m", w.street_min_m);
  read_vec2(s, "street_max_m", w.street_max_m);
  if (!(w.street_max_m.array() > w.street_min_m.array()).all())
    s.fail("street_max_m", "must be above street_min_m in x and y");
  read_positive(s, "building_setback_m", w.building_setback_m);
  read_positive(s, "pole_spacing_m", w.pole_spacing_m);
  read_positive(s, "parked_spacing_m", w.parked_spacing_m);
  read_non_negative(s, "clearance_m", w.clearance_m);
  read_non_negative(s, "repeat_x_m", w.repeat_x_m);
  const std::vector<double> boxes = read_groups(s, "boxes", 7, false);
  for (size_t i = 0; i < boxes.size(); i += 7) {
    BoxSpec b;
    b.center = Eigen::Vector3d(boxes[i], boxes[i + 1], boxes[i + 2]);
    b.size = Eigen::Vector3d(boxes[i + 3], boxes[i + 4], boxes[i + 5]);
    b.yaw_deg = boxes[i + 6];
    if (!(b.size.minCoeff() > 0.0)) s.fail("boxes", "box sizes must be positive");
    w.boxes.push_back(b);
  }
  const std::vector<double> regions = read_groups(s, "textureless_regions", 6, false);
  for (size_t i = 0; i < regions.size(); i += 6) {
    const Eigen::Vector3d lo(regions[i], regions[i + 1], regions[i + 2]);
    const Eigen::Vector3d hi(regions[i + 3], regions[i + 4], regions[i + 5]);
    if (!(hi.array() > lo.array()).all())
      s.fail("textureless_regions", "each region is min x y z, max x y z with max > min");
    w.textureless_regions.emplace_back(lo, hi);
  }
}

void read_yaw(ConfigSection& s, TrajectoryOptions& t) {
  const std::string mode = s.require<std::string>("mode");
  if (mode == "heading") {
    t.yaw_mode = YawMode::kHeading;
  } else if (mode == "keyframes") {
    t.yaw_mode = YawMode::kKeyframes;
  } else {
    s.fail("mode", "must be 'heading' or 'keyframes', got '" + mode + "'");
  }
  read_positive(s, "knot_s", t.yaw_knot_s);
  s.read("deg", t.yaw_deg);
  if (t.yaw_mode == YawMode::kKeyframes && t.yaw_deg.empty())
    s.fail("deg", "keyframe yaw needs at least one keyframe");
  if (t.yaw_mode == YawMode::kHeading && !t.closed)
    s.fail("mode", "heading yaw needs a closed path (trajectory.closed: true)");
}

// The path stays inside the world (minus the clearance) and clear of the explicit boxes.
void check_path(ConfigSection& s, const Scenario& sc, const Trajectory& trajectory) {
  const WorldSpec& w = sc.world;
  const Eigen::AlignedBox3d bounds = world_bounds(w);
  const double c = w.clearance_m;
  const Eigen::AlignedBox3d inner(bounds.min() + Eigen::Vector3d::Constant(c),
                                  bounds.max() - Eigen::Vector3d::Constant(c));
  const std::vector<Eigen::Vector3d> path = sample_path(trajectory, sc.duration_s, kPathCheckStepS);
  const auto nearest_waypoint = [&](const Eigen::Vector3d& p) {
    size_t best = 0;
    for (size_t i = 1; i < sc.trajectory.waypoints.size(); ++i)
      if ((sc.trajectory.waypoints[i] - p).norm() < (sc.trajectory.waypoints[best] - p).norm())
        best = i;
    return "near waypoint " + std::to_string(best) + " " +
           format_point(sc.trajectory.waypoints[best]);
  };
  for (size_t k = 0; k < path.size(); ++k) {
    const Eigen::Vector3d& p = path[k];
    const std::string when = " at t = " + std::to_string(k * kPathCheckStepS) + " s";
    if (!inner.contains(p))
      s.fail("waypoints", "the path leaves the world (bounds minus clearance_m " +
                              format_point(inner.min()) + " - " + format_point(inner.max()) +
                              ") at " + format_point(p) + when + ", " + nearest_waypoint(p));
    for (size_t i = 0; i < w.boxes.size(); ++i)
      if (distance_to_box(box_solid(w.boxes[i]), p) < c)
        s.fail("waypoints", "the path passes through world.boxes[" + std::to_string(i) +
                                "] (centre " + format_point(w.boxes[i].center) + ") at " +
                                format_point(p) + when + ", " + nearest_waypoint(p));
  }
}

void read_trajectory(ConfigSection& s, Scenario& sc) {
  TrajectoryOptions& t = sc.trajectory;
  const std::vector<double> wp = read_groups(s, "waypoints", 3, true);
  for (size_t i = 0; i < wp.size(); i += 3) t.waypoints.emplace_back(wp[i], wp[i + 1], wp[i + 2]);
  s.read("closed", t.closed);
  read_positive(s, "speed_mps", t.speed_mps);
  read_positive(s, "knot_s", t.knot_s);
  if (s.read("laps", t.laps) && t.laps < 1) s.fail("laps", "must be >= 1");
  read_non_negative(s, "start_hold_s", t.start_hold_s);
  read_positive(s, "ramp_s", t.ramp_s);
  s.read("tilt_gain", t.tilt_gain);
  t.yaw_mode = YawMode::kHeading;
  bool has_yaw = false;
  s.section("yaw", [&](ConfigSection& y) {
    has_yaw = true;
    read_yaw(y, t);
  });
  if (!has_yaw && !t.closed) s.fail("closed", "an open path needs a yaw section with keyframes");
  try {
    check_path(s, sc, Trajectory(t));
  } catch (const std::invalid_argument& e) {
    s.fail("waypoints", e.what());
  }
}

void read_imu(ConfigSection& s, ImuSynthOptions& imu) {
  read_positive(s, "rate_hz", imu.rate_hz);
  read_non_negative(s, "gyro_noise_density", imu.gyro_noise_density);
  read_non_negative(s, "gyro_random_walk", imu.gyro_random_walk);
  read_non_negative(s, "accel_noise_density", imu.accel_noise_density);
  read_non_negative(s, "accel_random_walk", imu.accel_random_walk);
  read_vec3(s, "gyro_bias", imu.gyro_bias);
  read_vec3(s, "accel_bias", imu.accel_bias);
}

void read_camera(ConfigSection& s, CameraSetup& cam) {
  read_positive(s, "rate_hz", cam.rate_hz);
  read_non_negative(s, "exposure_ms", cam.exposure_ms);
  if (cam.exposure_ms >= 1000.0 / cam.rate_hz)
    s.fail("exposure_ms", "must be shorter than the frame period");
  s.read("noise", cam.noise);
  s.read("motion_blur", cam.motion_blur);
  if (s.read("texture_size", cam.texture_size) &&
      (cam.texture_size < 16 || (cam.texture_size & (cam.texture_size - 1)) != 0))
    s.fail("texture_size", "must be a power of two >= 16");
}

void read_events(ConfigSection& s, Scenario& sc) {
  ScenarioEvents& e = sc.events;
  const std::vector<double> steps = read_groups(s, "gain_steps", 2, false);
  for (size_t i = 0; i < steps.size(); i += 2) {
    if (!(steps[i] >= 0.0) ||
        (!e.gain_steps.empty() && s_to_ns(steps[i]) <= e.gain_steps.back().t_ns))
      s.fail("gain_steps", "step times must be >= 0 and increasing");
    if (!(steps[i + 1] > 0.0)) s.fail("gain_steps", "gains must be positive");
    e.gain_steps.push_back({s_to_ns(steps[i]), steps[i + 1]});
  }
  e.blackouts = read_windows(s, "blackouts", sc.duration_s);
  std::string mode = "black";
  s.read("blackout_frames", mode);
  if (mode == "black") {
    e.blackout_mode = BlackoutMode::kBlack;
  } else if (mode == "missing") {
    e.blackout_mode = BlackoutMode::kMissing;
  } else {
    s.fail("blackout_frames", "must be 'black' or 'missing', got '" + mode + "'");
  }
  e.imu_gaps = read_windows(s, "imu_gaps", sc.duration_s);
  e.textureless = read_windows(s, "textureless", sc.duration_s);
}

std::string file_stem(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const size_t dot = name.find_last_of('.');
  return dot == std::string::npos ? name : name.substr(0, dot);
}

}  // namespace

double ScenarioEvents::gain_at(int64_t t_rel_ns) const {
  double gain = 1.0;
  for (const GainStep& step : gain_steps)
    if (t_rel_ns >= step.t_ns) gain = step.gain;
  return gain;
}

bool ScenarioEvents::in_blackout(int64_t t_rel_ns) const {
  for (const TimeWindow& w : blackouts)
    if (w.contains(t_rel_ns)) return true;
  return false;
}

std::vector<Eigen::Vector3d> sample_path(const Trajectory& trajectory, double duration_s,
                                         double step_s) {
  std::vector<Eigen::Vector3d> path;
  const long n = static_cast<long>(std::ceil(duration_s / step_s));
  for (long k = 0; k <= n; ++k)
    path.push_back(trajectory.at(std::min(duration_s, static_cast<double>(k) * step_s)).p_w_b);
  return path;
}

Scenario load_scenario(const std::string& path) {
  ConfigSection top = ConfigSection::load(path);
  Scenario sc;
  sc.source = path;
  sc.name = file_stem(path);
  top.read("name", sc.name);
  int64_t seed = static_cast<int64_t>(sc.seed);
  if (top.read("seed", seed) && seed < 0) top.fail("seed", "must be >= 0");
  sc.seed = static_cast<uint64_t>(seed);
  sc.duration_s = top.require<double>("duration_s");
  if (!(sc.duration_s > 0.0)) top.fail("duration_s", "must be positive");
  if (top.read("start_time_ns", sc.start_time_ns) && sc.start_time_ns < 0)
    top.fail("start_time_ns", "must be >= 0");
  bool has_world = false, has_trajectory = false;
  top.section("world", [&](ConfigSection& s) {
    has_world = true;
    read_world(s, sc.world);
  });
  if (!has_world) top.fail("world", "missing section");
  top.section("imu", [&](ConfigSection& s) { read_imu(s, sc.imu); });
  top.section("camera", [&](ConfigSection& s) { read_camera(s, sc.camera); });
  top.section("events", [&](ConfigSection& s) { read_events(s, sc); });
  top.section("trajectory", [&](ConfigSection& s) {
    has_trajectory = true;
    read_trajectory(s, sc);
  });
  if (!has_trajectory) top.fail("trajectory", "missing section");
  top.finish();
  return sc;
}

}  // namespace hs::sim
