// hs-bench-direct: speed of the direct tracking front end on one core, on a synthetic 752x480
// EuRoC-camera view of a textured room (tests/tracker/direct_scene.h) after an 8.5 cm / 3 deg
// motion, with an IMU-like initial error of 3 cm / 1.5 deg. Prints per call: sparse image
// alignment (4 levels) for 100/200/400 points, per-point refinement and optical flow per point,
// and OpenCV's pyramidal LK for scale. Times are thread CPU time (robust to other load).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <functional>
#include <opencv2/video/tracking.hpp>
#include <vector>

#include "common/calib/camera_calib.h"
#include "common/core/monotonic_clock.h"
#include "common/imu/so3.h"
#include "tests/tracker/direct_scene.h"
#include "tracker/direct_align.h"
#include "tracker/direct_patch.h"

namespace {

constexpr double kDeg = M_PI / 180.0;

Eigen::Isometry3d make_pose(const Eigen::Vector3d& t, const Eigen::Vector3d& rotvec) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = hs::so3::exp(rotvec);
  T.translation() = t;
  return T;
}

struct Stats {
  double mean_ms, median_ms;
};

// Runs `fn` `repeats` times (after one warm-up call) and returns its CPU time statistics.
Stats time_it(int repeats, const std::function<void()>& fn) {
  fn();
  std::vector<double> ms;
  for (int i = 0; i < repeats; ++i) {
    const double t0 = hs::thread_cpu_s();
    fn();
    ms.push_back(1e3 * (hs::thread_cpu_s() - t0));
  }
  std::sort(ms.begin(), ms.end());
  double sum = 0.0;
  for (const double x : ms) sum += x;
  return {sum / repeats, ms[ms.size() / 2]};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Speed of sparse image alignment and per-point patch alignment"};
  int repeats = 50;
  app.add_option("-n,--repeats", repeats, "timed calls per case")->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);

  const hs::PinholeRadtan cam = hs::euroc_stereo_calib().cam0.intrinsics;
  const hs::direct_test::RoomScene scene(cam);
  const Eigen::Isometry3d T_true =
      make_pose({0.06, -0.03, 0.05}, Eigen::Vector3d(0.3, -1.0, 0.5).normalized() * 3.0 * kDeg);
  const Eigen::Isometry3d T_init =
      T_true * make_pose(Eigen::Vector3d(1.0, -0.5, 0.7).normalized() * 0.03,
                         Eigen::Vector3d(-0.4, 0.8, 0.3).normalized() * 1.5 * kDeg);
  const cv::Mat ref_img = scene.render(Eigen::Isometry3d::Identity(), 1.0, 0.0, 1.5, 1);
  const cv::Mat cur_img = scene.render(T_true.inverse(), 1.1, 5.0, 1.5, 2);
  const hs::ImagePyramid ref = hs::build_pyramid(ref_img, 4);
  const hs::ImagePyramid cur = hs::build_pyramid(cur_img, 4);
  const Stats pyr = time_it(repeats, [&] { hs::build_pyramid(cur_img, 4); });
  std::printf("752x480, 4 levels, %d calls per case, thread CPU time\n", repeats);
  std::printf("build_pyramid: mean %.3f ms, median %.3f ms\n\n", pyr.mean_ms, pyr.median_ms);

  std::printf("sparse image alignment (4x4 patches, levels 3..0, IMU-like initial error)\n");
  std::printf("%7s %9s %11s %6s %8s %9s %9s %9s\n", "points", "mean ms", "median ms", "evals",
              "inliers", "err mm", "err deg", "us/point");
  hs::SparseAligner aligner;
  for (const int n : {100, 200, 400}) {
    const int cols = static_cast<int>(std::lround(std::sqrt(n * 1.6)));
    const int rows = (n + cols - 1) / cols;
    std::vector<Eigen::Vector3d> pts =
        hs::direct_test::select_points(scene, ref_img, Eigen::Isometry3d::Identity(), cols, rows);
    pts.resize(std::min(pts.size(), static_cast<size_t>(n)));
    hs::SparseAlignResult r;
    const Stats s = time_it(repeats, [&] { r = aligner.align(ref, cur, cam, pts, T_init); });
    const Eigen::Isometry3d E = T_true.inverse() * r.T_cur_ref;
    std::printf("%7zu %9.3f %11.3f %6d %8d %9.3f %9.4f %9.2f\n", pts.size(), s.mean_ms, s.median_ms,
                r.iterations, r.num_inliers, 1e3 * E.translation().norm(),
                hs::so3::log(Eigen::Matrix3d(E.linear())).norm() / kDeg,
                1e3 * s.mean_ms / static_cast<double>(pts.size()));
  }

  // Per-point work on 200 points: refinement after alignment (pose known to ~1 px, start at
  // level 0) and optical flow from the previous pixel (search radius 40 px, start at level 3).
  const std::vector<Eigen::Vector3d> pts =
      hs::direct_test::select_points(scene, ref_img, Eigen::Isometry3d::Identity(), 18, 11);
  const hs::PatchAlignOptions popt;
  const Eigen::Isometry3d T_near =
      T_true * make_pose(Eigen::Vector3d(0.003, 0.0, 0.0), Eigen::Vector3d(0.0, 0.1 * kDeg, 0.0));
  std::vector<hs::PatchAlignResult> results;
  const Stats refine = time_it(repeats, [&] {
    hs::refine_correspondences(ref, cur, cam, pts, T_near, 2.0, popt, &results);
  });
  const auto count_ok = [&] {
    return std::count_if(results.begin(), results.end(),
                         [](const hs::PatchAlignResult& r) { return r.ok(); });
  };
  const long refine_ok = count_ok();
  std::vector<Eigen::Vector2d> uv_prev;
  std::vector<cv::Point2f> cv_prev, cv_next;
  for (const auto& p : pts) {
    uv_prev.push_back(cam.project(p));
    cv_prev.emplace_back(static_cast<float>(uv_prev.back().x()),
                         static_cast<float>(uv_prev.back().y()));
  }
  const Stats flow = time_it(
      repeats, [&] { hs::track_optical_flow(ref, cur, uv_prev, uv_prev, 40.0, popt, &results); });
  const long flow_ok = count_ok();
  std::vector<uint8_t> status;
  std::vector<float> err;
  const Stats cv_flow = time_it(repeats, [&] {
    cv::calcOpticalFlowPyrLK(ref_img, cur_img, cv_prev, cv_next, status, err, cv::Size(8, 8), 3);
  });
  const double n = static_cast<double>(pts.size());
  std::printf("\nper-point patch alignment (8x8 patches), %zu points\n", pts.size());
  std::printf("%-34s %9s %11s %9s %6s\n", "", "mean ms", "median ms", "us/point", "ok");
  std::printf("%-34s %9.3f %11.3f %9.2f %6ld\n", "refine_correspondences (level 0)", refine.mean_ms,
              refine.median_ms, 1e3 * refine.mean_ms / n, refine_ok);
  std::printf("%-34s %9.3f %11.3f %9.2f %6ld\n", "track_optical_flow (levels 3..0)", flow.mean_ms,
              flow.median_ms, 1e3 * flow.mean_ms / n, flow_ok);
  std::printf("%-34s %9.3f %11.3f %9.2f %6ld\n", "cv::calcOpticalFlowPyrLK 8x8 (ref.)",
              cv_flow.mean_ms, cv_flow.median_ms, 1e3 * cv_flow.mean_ms / n,
              static_cast<long>(std::count(status.begin(), status.end(), 1)));
  return 0;
}
