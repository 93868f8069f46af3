#include "common/config/calibration_section.h"

#include <filesystem>

#include "common/config/yaml_file.h"
#include "common/core/error.h"

namespace hs {
namespace {

namespace fs = std::filesystem;

// Paths in a config are relative to the config file.
std::string resolve(const std::string& config_path, const std::string& path) {
  const fs::path p(path);
  return p.is_absolute() ? path : (fs::path(config_path).parent_path() / p).string();
}

}  // namespace

ImuNoise read_imu_yaml(const std::string& path) {
  const YAML::Node root = load_yaml_file(path);
  ImuNoise n;
  const auto get = [&](const char* key, double& out) {
    const YAML::Node v = root[key];
    if (!v) throw InputError(path, std::string("missing key '") + key + "'");
    try {
      out = v.as<double>();
    } catch (const YAML::Exception&) {
      throw InputError(path, v.Mark().line + 1, std::string("'") + key + "' must be a number");
    }
    if (!(out > 0))
      throw InputError(path, v.Mark().line + 1, std::string("'") + key + "' must be > 0");
  };
  get("gyroscope_noise_density", n.gyro_noise_density);
  get("gyroscope_random_walk", n.gyro_random_walk);
  get("accelerometer_noise_density", n.accel_noise_density);
  get("accelerometer_random_walk", n.accel_random_walk);
  get("rate_hz", n.rate_hz);
  return n;
}

void read_calibration_section(ConfigSection& s, const std::string& config_path, StereoCalib& calib,
                              ImuNoise& noise) {
  std::string cam0, cam1, imu;
  if (s.read("cam0", cam0)) calib.cam0 = read_camera_yaml(resolve(config_path, cam0));
  if (s.read("cam1", cam1)) calib.cam1 = read_camera_yaml(resolve(config_path, cam1));
  if (s.read("imu", imu)) noise = read_imu_yaml(resolve(config_path, imu));
}

}  // namespace hs
