#pragma once
// In-memory, streaming dataset generation: IMU samples and 200 Hz ground truth are made up front
// (small); stereo frames are rendered one at a time on request, so long sequences never hold
// more than one pair of images.
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "common/sim/imu_synth.h"
#include "common/sim/render.h"
#include "common/sim/scenario.h"
#include "common/sim/trajectory.h"
#include "common/sim/world.h"

namespace hs::sim {

struct GenerateOptions {
  bool render = true;    // false: no renderers (IMU, ground truth and frame times only)
  bool parallel = true;  // render cam1 on a second thread
};

struct SimStereoFrame {
  int64_t t_ns = 0;       // mid-exposure
  bool blackout = false;  // black frame from a blackout window
  cv::Mat cam0, cam1;     // CV_8UC1
};

// Seeds of the random streams derived from the scenario seed.
enum class SeedStream : uint64_t { kWorld = 1, kImu = 2, kImage = 3 };

class DatasetGenerator {
 public:
  DatasetGenerator(const Scenario& scenario, const GenerateOptions& options = {});
  ~DatasetGenerator();
  DatasetGenerator(const DatasetGenerator&) = delete;
  DatasetGenerator& operator=(const DatasetGenerator&) = delete;

  const Scenario& scenario() const { return scenario_; }
  const Trajectory& trajectory() const { return trajectory_; }
  const World& world() const { return world_; }
  const ImuSeries& imu() const { return imu_; }  // samples (gaps left out) + ground truth
  // Frame times (mid-exposure); frames of 'missing' blackouts are left out.
  const std::vector<int64_t>& frame_times_ns() const { return frame_times_ns_; }
  size_t num_frames() const { return frame_times_ns_.size(); }

  // Renders frame i. Needs options.render.
  SimStereoFrame frame(size_t i);

  // Exact body kinematics at an absolute time.
  BodyKinematics body_at(int64_t t_ns) const;
  Eigen::Isometry3d T_w_b(int64_t t_ns) const;

 private:
  Scenario scenario_;
  GenerateOptions options_;
  Trajectory trajectory_;
  World world_;
  ImuSeries imu_;
  std::vector<int64_t> frame_times_ns_;
  std::unique_ptr<Renderer> cam0_, cam1_;
};

}  // namespace hs::sim
