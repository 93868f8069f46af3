#pragma once
// The --calib DIR / --calib-from-sim SCENARIO options of the LCM processes: where the stereo
// rig's calibration comes from when not from the config.
#include <CLI/CLI.hpp>
#include <string>

#include "common/calib/camera_calib.h"

namespace hs {

// Adds --calib and --calib-from-sim (mutually exclusive), storing into the two strings.
inline void add_rig_calib_options(CLI::App& app, std::string& calib_dir,
                                  std::string& sim_scenario) {
  auto* calib = app.add_option("--calib", calib_dir, "EuRoC folder (root or mav0/) for cameras");
  app.add_option("--calib-from-sim", sim_scenario, "use this sim scenario's camera calibration")
      ->excludes(calib);
}

// `calib_dir`: a EuRoC folder (root or mav0/) with cam0/cam1 sensor.yaml; `sim_scenario`: a
// scenario whose camera to use. Empty strings leave `calib` as it is.
void override_rig_calib(const std::string& calib_dir, const std::string& sim_scenario,
                        StereoCalib& calib);

}  // namespace hs
