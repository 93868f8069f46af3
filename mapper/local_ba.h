#pragma once
// Local visual-inertial bundle adjustment over a window of keyframes (issue 6), in Ceres:
// reprojection residuals (Huber), preintegrated IMU factors and bias random walk between
// consecutive keyframes. Pure optimiser: the inputs are plain structs, independent of the
// keyframe graph, and refer to each other by id.
//
// Robust scheme as in ORB-SLAM's local BA: optimise, drop the observations failing the chi2
// test, optimise again; the outlier flags come from the chi2 test at the final estimate.
// Gauge: keyframes flagged `fixed` are held constant (pose, velocity and biases), `pose_fixed`
// ones only in pose; when none is, the pose of the oldest keyframe is held. With no points the
// same solver is an inertial-only optimisation of velocities, biases and gravity on fixed poses.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "common/calib/camera_calib.h"
#include "common/core/types.h"
#include "common/imu/imu_residual.h"
#include "common/imu/preintegration.h"

namespace hs {

struct LocalBaOptions {
  int iterations_per_round = 10;  // Levenberg-Marquardt iterations
  // A round stops when an iteration lowers the cost by less than this share.
  double function_tolerance = 1e-6;
  // ... the first of two rounds, which only has to find the outliers. 1e-4 takes the room_mav
  // BA from 12.6 to 8.8 iterations (CPU median 63 -> 48 ms) at the same ATE, but moves two
  // chaotic vehicle tests (see README); the default stays at the second round's.
  double screening_function_tolerance = 1e-6;
  bool reject_outliers = true;  // second round without the chi2 outliers of the first
  // Limit on the CPU time of the calling thread over both rounds (num_threads 1); the solver
  // stops with its current estimate after the iteration that crosses it.
  double time_budget_ms = 100.0;
  double chi2_threshold = 5.991;  // 95% of chi2 with 2 DoF: Huber threshold and outlier test
  double min_depth_m = 0.05;      // nearer to a camera: the observation cannot be used
  int num_threads = 1;
  // The reduced keyframe system solved sparse: for the whole map (full BA), where most
  // keyframes share no point and a dense one would be cubic in their number.
  bool sparse = false;
  // Ceres' Levenberg-Marquardt, or the same step control in mapper/schur_lm.h, which skips
  // Ceres' general machinery (0.4x the CPU time in hs-bench-local-ba). Ceres still solves the
  // `sparse` problems and those without points (inertial chains).
  enum class Solver { kCeres, kSchurLm } solver = Solver::kSchurLm;
};

struct BaKeyframe {
  int64_t id = 0;
  NavState state;           // t_ns must match the IMU factors' ends
  bool fixed = false;       // pose, velocity and biases held
  bool pose_fixed = false;  // pose held, velocity and biases free (inertial-only refinement)
};

struct BaPoint {
  int64_t id = 0;
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
  bool fixed = false;
};

// A point seen in one camera. A stereo observation is two of these (camera 0 and 1): EuRoC's
// images are not rectified, so the right view is a full 2D measurement.
struct BaObservation {
  int64_t keyframe_id = 0;
  int64_t point_id = 0;
  int camera = 0;                                // 0: cam0 (left), 1: cam1 (right)
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  // distorted pixel
  double sigma_px = 1.0;                         // per axis, e.g. from the pyramid level
};

// Preintegration from keyframe i's time to keyframe j's time.
struct BaImuFactor {
  int64_t keyframe_i = 0;
  int64_t keyframe_j = 0;
  ImuPreintegration pim;
};

// Gravity in the world frame: held at g_w, or its direction estimated (the magnitude stays)
// with a prior of prior_sigma_rad around g_w. A world levelled at rest from the mean
// acceleration is tilted by the accelerometer bias (0.1 m/s^2 is 0.6 deg), and only motion
// tells the two apart.
struct BaGravity {
  Eigen::Vector3d g_w = default_gravity_w();
  double prior_sigma_rad = 0.0;  // <= 0: held fixed
};

struct LocalBaInput {
  BaGravity gravity;
  std::vector<BaKeyframe> keyframes;
  std::vector<BaPoint> points;
  std::vector<BaObservation> observations;
  std::vector<BaImuFactor> imu_factors;
};

struct LocalBaStats {
  double initial_cost = 0.0;  // Ceres cost (0.5 sum of robustified squared residuals)
  double final_cost = 0.0;    // of the last round (without the removed outliers)
  int iterations = 0;         // over all rounds
  int rounds = 0;
  int num_outliers = 0;
  double time_ms = 0.0;  // wall clock of the whole call
  double cpu_ms = 0.0;   // this thread's CPU time of it (other load on the cores does not count)
};

struct LocalBaResult {
  std::vector<BaKeyframe> keyframes;              // input order, updated
  std::vector<BaPoint> points;                    // input order, updated
  Eigen::Vector3d g_w = Eigen::Vector3d::Zero();  // the input's, or its estimate
  // Per observation: failed the chi2 test at the final estimate, or could not be projected.
  std::vector<bool> outliers;
  LocalBaStats stats;
};

class LocalBundleAdjuster {
 public:
  LocalBundleAdjuster(const StereoCalib& calib, const LocalBaOptions& options = {});

  // Throws std::invalid_argument naming the element for malformed input: duplicate or unknown
  // ids, camera index not 0/1, non-finite values, sigma <= 0, an IMU factor whose
  // preintegration does not span its keyframes' times, a zero or non-finite gravity.
  LocalBaResult optimise(const LocalBaInput& input) const;

 private:
  StereoCalib calib_;
  LocalBaOptions options_;
};

}  // namespace hs
