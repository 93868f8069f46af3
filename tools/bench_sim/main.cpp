// hs-bench-sim: speed of the stereo image renderer on one core, in the scenarios' furnished
// room world (common/sim/world_gen.h) seen from a camera circling inside it. Prints images/s,
// stereo frames/s and the time per stage, first with the default effects (noise and
// vignetting), then with motion blur added.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "common/calib/camera_calib.h"
#include "common/core/monotonic_clock.h"
#include "common/sim/render.h"
#include "common/sim/world_gen.h"

namespace {

constexpr double kRadiusM = 1.5, kHeightM = 1.4, kFrameS = 0.05;  // 20 Hz

// Camera on a circle inside the room, looking outwards and a little down; `a` is the angle
// along the circle (rad).
Eigen::Isometry3d circle_pose(double a) {
  const Eigen::Vector3d z =
      Eigen::Vector3d(std::cos(a + 0.6), std::sin(a + 0.6), -0.15).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
  T_w_c.linear().col(0) = x;
  T_w_c.linear().col(1) = z.cross(x);
  T_w_c.linear().col(2) = z;
  T_w_c.translation() = Eigen::Vector3d(kRadiusM * std::cos(a), kRadiusM * std::sin(a), kHeightM);
  return T_w_c;
}

hs::sim::World room_world(int furniture) {
  hs::sim::WorldSpec spec;
  spec.furniture = furniture;
  std::vector<Eigen::Vector3d> path;
  for (int i = 0; i < 360; ++i) path.push_back(circle_pose(i * M_PI / 180.0).translation());
  return hs::sim::generate_world(spec, path, 7);
}

struct Settings {
  int frames = 200;
  double angular_speed = 1.0;  // rad/s along the circle (1.5 m/s)
  double exposure_ms = 4.0;
  std::string save_dir;
};

void run(const char* title, const hs::sim::World& world, const hs::sim::RenderOptions& options,
         bool blur, const Settings& s) {
  const hs::StereoCalib calib = hs::euroc_stereo_calib();
  const double cpu_build = hs::thread_cpu_s();
  hs::sim::Renderer cam0(world, calib.cam0.intrinsics, options);
  hs::sim::Renderer cam1(cam0, calib.cam1.intrinsics, options);
  const double build_s = hs::thread_cpu_s() - cpu_build;
  const Eigen::Isometry3d T_c0_c1 = calib.T_c0_c1();

  const auto wall0 = std::chrono::steady_clock::now();
  const double cpu0 = hs::thread_cpu_s();
  for (int i = 0; i < s.frames; ++i) {
    const double a = i * kFrameS * s.angular_speed;
    const double da = s.angular_speed * s.exposure_ms * 1e-3;  // angle during the exposure
    hs::sim::FrameParams f0, f1;
    f0.noise_seed = 2 * static_cast<uint64_t>(i);
    f1.noise_seed = f0.noise_seed + 1;
    if (blur) {
      f0.T_w_c_at = [&](double t) { return circle_pose(a + (t - 0.5) * da); };
      f1.T_w_c_at = [&](double t) { return circle_pose(a + (t - 0.5) * da) * T_c0_c1; };
    }
    const cv::Mat img0 = cam0.render(circle_pose(a), f0);
    const cv::Mat img1 = cam1.render(circle_pose(a) * T_c0_c1, f1);
    if (i == 0 && !s.save_dir.empty()) {
      const std::string tag = blur ? "_blur" : "";
      cv::imwrite(s.save_dir + "/bench_cam0" + tag + ".png", img0);
      cv::imwrite(s.save_dir + "/bench_cam1" + tag + ".png", img1);
    }
  }
  const double cpu_s = hs::thread_cpu_s() - cpu0;
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();

  hs::sim::RenderStats t = cam0.stats();
  const hs::sim::RenderStats& t1 = cam1.stats();
  t.images += t1.images;
  t.setup_ns += t1.setup_ns;
  t.visibility_ns += t1.visibility_ns;
  t.shading_ns += t1.shading_ns;
  t.blur_ns += t1.blur_ns;
  t.photometric_ns += t1.photometric_ns;
  t.edge_pixels += t1.edge_pixels;
  t.blurred_tiles += t1.blurred_tiles;
  const double n = static_cast<double>(t.images);
  const auto ms = [n](int64_t ns) { return 1e-6 * static_cast<double>(ns) / n; };

  std::printf("\n== %s\n", title);
  std::printf("renderers built in %.2f s CPU (%zu quads, texture size %d)\n", build_s,
              world.quads.size(), options.texture_size);
  std::printf("%lld images (%d stereo frames) 752x480, one thread: %.3f s CPU, %.3f s wall\n",
              static_cast<long long>(t.images), s.frames, cpu_s, wall_s);
  std::printf("images/s:        %.1f\n", n / cpu_s);
  std::printf("stereo frames/s: %.1f\n", s.frames / cpu_s);
  std::printf("ms per image:    %.3f\n", 1e3 * cpu_s / n);
  std::printf("  setup+binning  %.3f ms\n", ms(t.setup_ns));
  std::printf("  raster (vis.)  %.3f ms\n", ms(t.visibility_ns));
  std::printf("  shading+AA     %.3f ms  (%.0f edge pixels/image)\n", ms(t.shading_ns),
              static_cast<double>(t.edge_pixels) / n);
  std::printf("  distortion     0.000 ms  (per-pixel rays: no remap stage)\n");
  std::printf("  motion blur    %.3f ms  (%.1f of 1410 tiles/image re-rendered)\n", ms(t.blur_ns),
              static_cast<double>(t.blurred_tiles) / n);
  std::printf("  gain/vig/noise %.3f ms\n", ms(t.photometric_ns));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Benchmarks the stereo image renderer on one core."};
  Settings s;
  int furniture = 10, texture_size = 1024;
  app.add_option("--frames", s.frames, "stereo frames per pass")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--angular-speed", s.angular_speed, "rad/s along the 1.5 m circle")
      ->capture_default_str();
  app.add_option("--exposure-ms", s.exposure_ms, "exposure time for motion blur")
      ->capture_default_str();
  app.add_option("--furniture", furniture, "objects in the room")->capture_default_str();
  app.add_option("--texture-size", texture_size, "texels per texture tile")->capture_default_str();
  app.add_option("--save-dir", s.save_dir, "write each pass's first stereo pair as PNGs here");
  CLI11_PARSE(app, argc, argv);

  std::printf("(rates use the thread's CPU time; wall time is longer when the machine is busy)\n");
  const hs::sim::World world = room_world(furniture);
  hs::sim::RenderOptions options;  // noise and vignetting on
  options.texture_size = texture_size;
  options.motion_blur = false;
  run("default effects: noise + vignetting", world, options, false, s);
  options.motion_blur = true;
  run("noise + vignetting + motion blur", world, options, true, s);
  return 0;
}
