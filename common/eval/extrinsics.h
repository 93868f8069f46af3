#pragma once
// Reads the body<-camera transform T_b_c (EuRoC's T_BS: maps camera-frame points into the body
// frame, p_b = T_b_c * p_c) from 16 row-major numbers or a EuRoC sensor.yaml.
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace hs {

// Throws InputError unless `values` holds 16 numbers forming a rigid transform
// (orthonormal rotation, last row 0 0 0 1). `source` names where they came from.
Eigen::Isometry3d T_b_c_from_values(const std::vector<double>& values, const std::string& source);

// T_BS of a EuRoC camera sensor.yaml (read by common/calib).
Eigen::Isometry3d load_T_b_c_yaml(const std::string& path);

// Command-line form: one argument is a sensor.yaml path, sixteen are the matrix entries.
Eigen::Isometry3d parse_T_b_c(const std::vector<std::string>& args);

}  // namespace hs
