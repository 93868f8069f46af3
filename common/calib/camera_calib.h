#pragma once
// Camera intrinsics + extrinsics, and reading/writing EuRoC sensor.yaml files.
#include <Eigen/Geometry>
#include <string>

#include "common/calib/pinhole_radtan.h"

namespace hs {

struct CameraCalib {
  PinholeRadtan intrinsics;
  Eigen::Isometry3d T_b_c = Eigen::Isometry3d::Identity();  // camera -> body (EuRoC T_BS)
  double rate_hz = 20.0;
};

struct StereoCalib {
  CameraCalib cam0;
  CameraCalib cam1;

  // cam1 -> cam0.
  Eigen::Isometry3d T_c0_c1() const { return cam0.T_b_c.inverse() * cam1.T_b_c; }
  // Distance between the optical centres, metres.
  double baseline() const { return T_c0_c1().translation().norm(); }
};

// The EuRoC MAV dataset's calibration (cam0/cam1 sensor.yaml of the VI-Sensor).
StereoCalib euroc_stereo_calib();

// Reads a EuRoC camera sensor.yaml (the leading "%YAML:1.0" line is allowed). Only the
// pinhole camera model with radial-tangential distortion is supported. Throws InputError
// naming the file (and line when known) for unreadable files, bad values or other models.
CameraCalib read_camera_yaml(const std::string& path);
// Writes the same layout as EuRoC (including the "%YAML:1.0" line), atomically.
void write_camera_yaml(const std::string& path, const CameraCalib& calib,
                       const std::string& comment = "");

// Reads <mav0_dir>/cam0/sensor.yaml and <mav0_dir>/cam1/sensor.yaml. A mono rig's folder has no
// cam1: cam1 is then a copy of cam0 (a mono tracker never uses it).
StereoCalib read_stereo_calib(const std::string& mav0_dir);

}  // namespace hs
