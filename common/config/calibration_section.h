#pragma once
// The `calibration:` section shared by the tracker and mapper configs: EuRoC sensor.yaml files
// for cam0, cam1 and the IMU noise model, paths relative to the config file.
#include <string>

#include "common/calib/camera_calib.h"
#include "common/config/config_section.h"
#include "common/imu/imu_options.h"

namespace hs {

// Reads the keys cam0, cam1, imu (each optional: the defaults stay) from `section` of the
// config at `config_path`. Bad files: InputError naming the file and line.
void read_calibration_section(ConfigSection& section, const std::string& config_path,
                              StereoCalib& calib, ImuNoise& noise);

// The noise model of an EuRoC/Kalibr IMU sensor.yaml.
ImuNoise read_imu_yaml(const std::string& path);

}  // namespace hs
