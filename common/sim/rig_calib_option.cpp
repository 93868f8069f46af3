#include "common/sim/rig_calib_option.h"

#include <filesystem>

#include "common/sim/scenario.h"

namespace hs {

void override_rig_calib(const std::string& calib_dir, const std::string& sim_scenario,
                        StereoCalib& calib) {
  if (!calib_dir.empty()) {
    const std::filesystem::path mav0 = std::filesystem::path(calib_dir) / "mav0";
    calib = read_stereo_calib(std::filesystem::exists(mav0) ? mav0.string() : calib_dir);
  }
  if (!sim_scenario.empty()) calib = sim::load_scenario(sim_scenario).camera.calib;
}

}  // namespace hs
