#include "common/sim/dataset_gen.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <stdexcept>

#include "common/sim/scenario_random.h"

namespace hs::sim {
namespace {

constexpr double kWorldPathStepS = 0.05;
constexpr float kSkyRadiance = 190.0f;  // outdoor background: a bright, featureless sky

RenderOptions render_options(const CameraSetup& camera, WorldType world) {
  RenderOptions options;
  if (world == WorldType::kStreet) options.background = kSkyRadiance;
  options.photometric.noise = camera.noise;
  options.motion_blur = camera.motion_blur;
  options.texture_size = camera.texture_size;
  return options;
}

}  // namespace

DatasetGenerator::DatasetGenerator(const Scenario& scenario, const GenerateOptions& options)
    : scenario_(scenario), options_(options), trajectory_(scenario.trajectory) {
  const Scenario& sc = scenario_;
  // The whole motion, whatever the duration, so a shortened run shows the same world.
  const double path_end_s = std::max(sc.duration_s, trajectory_.motion_end_s());
  world_ = generate_world(sc.world, sample_path(trajectory_, path_end_s, kWorldPathStepS),
                          stream_seed(sc.seed, static_cast<uint64_t>(SeedStream::kWorld)));
  ImuSynthOptions imu_options = sc.imu;
  imu_options.gaps = sc.events.imu_gaps;
  const int64_t t_end_ns = sc.start_time_ns + s_to_ns(sc.duration_s);
  imu_ = synthesize_imu(trajectory_, imu_options, sc.start_time_ns, t_end_ns,
                        stream_seed(sc.seed, static_cast<uint64_t>(SeedStream::kImu)));
  const int64_t frame_period_ns = std::llround(kNsPerSec / sc.camera.rate_hz);
  for (int64_t t_ns = sc.start_time_ns; t_ns <= t_end_ns; t_ns += frame_period_ns) {
    const bool dark = sc.events.in_blackout(t_ns - sc.start_time_ns);
    if (dark && sc.events.blackout_mode == BlackoutMode::kMissing) continue;
    frame_times_ns_.push_back(t_ns);
  }
  if (options_.render) {
    const RenderOptions ro = render_options(sc.camera, sc.world.type);
    cam0_ = std::make_unique<Renderer>(world_, sc.camera.calib.cam0.intrinsics, ro);
    cam1_ = std::make_unique<Renderer>(*cam0_, sc.camera.calib.cam1.intrinsics, ro);
  }
}

DatasetGenerator::~DatasetGenerator() = default;

BodyKinematics DatasetGenerator::body_at(int64_t t_ns) const {
  return trajectory_.at(ns_to_s(t_ns - scenario_.start_time_ns));
}

Eigen::Isometry3d DatasetGenerator::T_w_b(int64_t t_ns) const {
  const BodyKinematics k = body_at(t_ns);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = k.q_w_b.toRotationMatrix();
  T.translation() = k.p_w_b;
  return T;
}

SimStereoFrame DatasetGenerator::frame(size_t i) {
  if (!cam0_) throw std::logic_error("DatasetGenerator::frame: generator made without rendering");
  const Scenario& sc = scenario_;
  SimStereoFrame out;
  out.t_ns = frame_times_ns_.at(i);
  const int64_t t_rel_ns = out.t_ns - sc.start_time_ns;
  out.blackout = sc.events.in_blackout(t_rel_ns);
  // Noise seeds follow the frame's slot in the 20 Hz schedule, so they do not depend on which
  // frames are skipped or on the requested duration.
  const uint64_t slot = static_cast<uint64_t>(std::llround(ns_to_s(t_rel_ns) * sc.camera.rate_hz));
  const uint64_t image_seed = stream_seed(sc.seed, static_cast<uint64_t>(SeedStream::kImage));
  const int64_t exposure_ns = s_to_ns(sc.camera.exposure_ms * 1e-3);

  const auto render = [&](Renderer& renderer, const CameraCalib& cam, uint64_t index) {
    FrameParams params;
    params.gain = sc.events.gain_at(t_rel_ns);
    params.blackout = out.blackout;
    params.noise_seed = splitmix64(image_seed ^ (2 * slot + index));
    if (sc.camera.motion_blur && exposure_ns > 0) {
      params.T_w_c_at = [this, &cam, t = out.t_ns, exposure_ns](double fraction) {
        const int64_t dt = std::llround((fraction - 0.5) * static_cast<double>(exposure_ns));
        return T_w_b(t + dt) * cam.T_b_c;
      };
    }
    return renderer.render(T_w_b(out.t_ns) * cam.T_b_c, params);
  };
  if (options_.parallel) {
    // The future waits for cam1 even when cam0 throws.
    std::future<cv::Mat> cam1 =
        std::async(std::launch::async, [&] { return render(*cam1_, sc.camera.calib.cam1, 1); });
    out.cam0 = render(*cam0_, sc.camera.calib.cam0, 0);
    out.cam1 = cam1.get();
  } else {
    out.cam0 = render(*cam0_, sc.camera.calib.cam0, 0);
    out.cam1 = render(*cam1_, sc.camera.calib.cam1, 1);
  }
  return out;
}

}  // namespace hs::sim
