#pragma once
// Writes a generated dataset in the EuRoC MAV layout:
//   DIR/mav0/{cam0,cam1}/data/<t_ns>.png + data.csv + sensor.yaml
//   DIR/mav0/imu0/data.csv + sensor.yaml
//   DIR/mav0/state_groundtruth_estimate0/data.csv   (p, q wxyz, v, gyro bias, accel bias)
//   DIR/mav0/body.yaml, DIR/sim_info.json (scenario name, seed, events)
// Everything goes into a temporary sibling directory that is renamed to DIR only when complete,
// so a half-finished run never looks like a dataset. Same scenario and seed -> identical bytes.
#include <cstddef>
#include <functional>
#include <string>

#include "common/sim/dataset_gen.h"

namespace hs::sim {

struct EurocWriteOptions {
  int png_compression = 1;  // zlib level 0-9: low is much faster and only slightly larger
  bool overwrite = false;   // replace an existing DIR (only once the new one is complete)
  // Called after each written frame with (frames done, frames total).
  std::function<void(size_t, size_t)> progress;
};

// Throws InputError when DIR exists (without overwrite) or cannot be written.
void write_euroc(DatasetGenerator& generator, const std::string& out_dir,
                 const EurocWriteOptions& options = {});

}  // namespace hs::sim
