#include "common/imu/vi_alignment.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <random>

#include "common/dataset/euroc_csv.h"
#include "common/imu/so3.h"
#include "tests/imu/analytic_motion.h"

namespace hs {
namespace {

using test::AnalyticMotion;

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// Constant world velocity and constant body rate: straight constant-velocity driving when
// omega_b = 0, rotation in place when v_w = 0.
struct UniformMotion {
  Eigen::Vector3d p0{1.0, 2.0, 0.5};
  Eigen::Vector3d v_w = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R0 = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Eigen::Vector3d omega_b = Eigen::Vector3d::Zero();

  Eigen::Matrix3d R(double t) const { return R0 * so3::exp(omega_b * t); }
  NavState state(int64_t t_ns) const {
    const double t = ns_to_s(t_ns);
    NavState s;
    s.t_ns = t_ns;
    s.p_w_b = p0 + v_w * t;
    s.q_w_b = Eigen::Quaterniond(R(t));
    s.v_w = v_w;
    return s;
  }
  ImuSample sample(int64_t t_ns, const ImuBias& bias) const {
    ImuSample s;
    s.t_ns = t_ns;
    s.gyro = omega_b + bias.gyro;
    s.accel = -R(ns_to_s(t_ns)).transpose() * default_gravity_w() + bias.accel;
    return s;
  }
};

struct Noise {
  double imu_scale = 1.0;  // times the EuRoC white noise
  double position_m = 0.0;
  double rotation_rad = 0.0;
};

// The vision world: tilted by 10 deg roll and 5 deg pitch, with an arbitrary yaw and origin.
Eigen::Isometry3d vision_from_world() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(2.3, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(5.0 * kDeg, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(10.0 * kDeg, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(3.0, -2.0, 1.0);
  return T;
}

struct Window {
  std::vector<TimedPose> poses;
  std::vector<ImuPreintegration> pims;
  std::vector<Eigen::Vector3d> v_v;  // true velocities in the vision world
};

// `n` poses every 50 ms (20 Hz) from t0_ns, with 200 Hz IMU preintegrated at zero bias.
template <class Motion>
Window make_window(const Motion& motion, int64_t t0_ns, int n, const ImuBias& bias,
                   const Noise& noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  const auto gaussian = [&](double sigma) {
    Eigen::Vector3d n;
    for (int k = 0; k < 3; ++k) n[k] = sigma * normal(rng);
    return n;
  };
  const ImuOptions imu;
  const double gyro_sigma =
      noise.imu_scale * imu.noise.gyro_noise_density * std::sqrt(imu.noise.rate_hz);
  const double accel_sigma =
      noise.imu_scale * imu.noise.accel_noise_density * std::sqrt(imu.noise.rate_hz);
  const int64_t frame_period = 50'000'000, imu_period = 5'000'000;
  const int64_t t_end = t0_ns + (n - 1) * frame_period;
  std::vector<ImuSample> samples;
  for (int64_t t = t0_ns - 2 * imu_period; t <= t_end + 2 * imu_period; t += imu_period) {
    ImuSample s = motion.sample(t, bias);
    s.gyro += gaussian(gyro_sigma);
    s.accel += gaussian(accel_sigma);
    samples.push_back(s);
  }
  const Eigen::Isometry3d T_v_w = vision_from_world();
  Window w;
  for (int i = 0; i < n; ++i) {
    const NavState s = motion.state(t0_ns + i * frame_period);
    Eigen::Isometry3d T_v_b = T_v_w * s.T_w_b();
    T_v_b.linear() = T_v_b.linear() * so3::exp(gaussian(noise.rotation_rad));
    T_v_b.translation() += gaussian(noise.position_m);
    w.poses.push_back({s.t_ns, T_v_b});
    w.v_v.push_back(T_v_w.linear() * s.v_w);
    if (i > 0) w.pims.push_back(preintegrate(samples, w.poses[i - 1].t_ns, s.t_ns, ImuBias{}));
  }
  return w;
}

ViAlignmentOptions options_for(const Noise& noise) {
  ViAlignmentOptions o;
  // A floor keeps the weights sane for noise-free poses.
  o.vision_position_sigma_m = std::max(noise.position_m, 1e-5);
  o.vision_rotation_sigma_rad = std::max(noise.rotation_rad, 1e-6);
  return o;
}

struct Errors {
  double tilt_deg;     // gravity direction in the vision world
  double aligned_deg;  // tilt left in R_wg_w * R_v_w (pure yaw when perfect)
  double gyro_bias;    // max abs, rad/s
  double velocity;     // max norm, m/s
};

Errors errors(const ViAlignmentResult& r, const Window& w, const ImuBias& bias) {
  const Eigen::Matrix3d R_v_w = vision_from_world().linear();
  const Eigen::Vector3d true_g_v = R_v_w * default_gravity_w();
  const auto angle_deg = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::atan2(a.cross(b).norm(), a.dot(b)) / kDeg;
  };
  Errors e{};
  e.tilt_deg = angle_deg(r.g_w, true_g_v);
  e.aligned_deg = angle_deg(r.R_wg_w * R_v_w * Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ());
  e.gyro_bias = (r.gyro_bias - bias.gyro).cwiseAbs().maxCoeff();
  for (size_t i = 0; i < w.v_v.size(); ++i) {
    e.velocity = std::max(e.velocity, (r.v_w[i] - w.v_v[i]).norm());
  }
  return e;
}

// Five noise draws of a moving start, each checked against the accuracy targets and against
// the uncertainty the alignment reports.
void check_moving_start(int n, const Noise& noise) {
  const AnalyticMotion motion;
  ImuBias bias;
  bias.gyro = {0.02, -0.015, 0.01};
  Errors worst{};
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const Window w = make_window(motion, s_to_ns(1.0 + 0.3 * seed), n, bias, noise, seed);
    const ViAlignmentResult r = align_visual_inertial(w.poses, w.pims, options_for(noise));
    ASSERT_TRUE(r.ok) << r.reason;
    ASSERT_EQ(r.v_w.size(), w.poses.size());
    EXPECT_NEAR(r.g_w.norm(), kGravityMagnitude, 1e-9);
    const Errors e = errors(r, w, bias);
    EXPECT_LT(e.tilt_deg, 0.1);
    EXPECT_LT(e.aligned_deg, 0.1);
    EXPECT_LT(e.gyro_bias, 1e-3);
    EXPECT_LT(e.velocity, 0.01);
    // The gravity-aligned frame points gravity straight down, rotating about a horizontal axis.
    EXPECT_LT((r.R_wg_w * r.g_w - default_gravity_w()).norm(), 1e-9);
    const Eigen::AngleAxisd R_wg_w(r.R_wg_w);
    EXPECT_NEAR(R_wg_w.axis().z() * R_wg_w.angle(), 0.0, 1e-9);
    // The noise model matches the data, so the fit statistics and sigmas must agree with it.
    EXPECT_LT(e.tilt_deg * kDeg, 4.0 * r.tilt_sigma_rad);
    EXPECT_LT(e.gyro_bias, 4.0 * r.gyro_bias_sigma);
    EXPECT_GT(r.rotation_chi2_per_dof, 0.5);
    EXPECT_LT(r.rotation_chi2_per_dof, 2.0);
    EXPECT_GT(r.translation_chi2_per_dof, 0.5);
    EXPECT_LT(r.translation_chi2_per_dof, 2.0);
    // The true accel bias is zero: an estimate must find that, within its uncertainty.
    if (r.accel_bias_estimated) {
      EXPECT_LT(r.accel_bias.norm(), 4.0 * r.accel_bias_sigma);
    }
    worst = {std::max(worst.tilt_deg, e.tilt_deg), std::max(worst.aligned_deg, e.aligned_deg),
             std::max(worst.gyro_bias, e.gyro_bias), std::max(worst.velocity, e.velocity)};
    if (seed == 1) {
      std::cout << n << " poses, seed 1: tilt sigma " << r.tilt_sigma_rad / kDeg
                << " deg, gyro bias sigma " << r.gyro_bias_sigma << " rad/s, accel bias sigma "
                << r.accel_bias_sigma << " m/s^2 (estimated " << r.accel_bias_estimated
                << "), conditioning " << r.gravity_accel_bias_conditioning << ", |g| free "
                << r.gravity_norm_unconstrained << ", corrections " << r.rotation_correction_rms_rad
                << " rad " << r.position_correction_rms_m << " m, chi2/dof "
                << r.rotation_chi2_per_dof << " " << r.translation_chi2_per_dof << "\n";
    }
  }
  std::cout << n << " poses, vision noise " << noise.position_m * 1e3 << " mm "
            << noise.rotation_rad / kDeg << " deg, worst of 5: tilt " << worst.tilt_deg
            << " deg, aligned tilt " << worst.aligned_deg << " deg, gyro bias " << worst.gyro_bias
            << " rad/s, velocity " << worst.velocity << " m/s\n";
}

TEST(ViAlignment, MovingStartTwoSeconds) {
  check_moving_start(41, Noise{1.0, 0.001, 0.02 * kDeg});
}

// Half the window: the velocity error grows about as T^-1.5, so the vision is better here
// (with 1 mm the worst velocity error of these draws is ~1 cm/s).
TEST(ViAlignment, MovingStartOneSecond) {
  check_moving_start(21, Noise{1.0, 0.0005, 0.02 * kDeg});
}

TEST(ViAlignment, AccelBiasEstimatedWhenRotationSeparatesIt) {
  const AnalyticMotion motion;
  ImuBias bias;
  bias.gyro = {-0.01, 0.02, 0.005};
  bias.accel = {0.08, -0.05, 0.1};
  const Noise exact{0.0, 0.0, 0.0};
  const Window w = make_window(motion, s_to_ns(2.0), 41, bias, exact, 7);
  const ViAlignmentResult r = align_visual_inertial(w.poses, w.pims, options_for(exact));
  ASSERT_TRUE(r.ok) << r.reason;
  ASSERT_TRUE(r.accel_bias_estimated) << "accel bias sigma " << r.accel_bias_sigma;
  EXPECT_FALSE(r.weak_excitation);
  const Errors e = errors(r, w, bias);
  const double ba_err = (r.accel_bias - bias.accel).norm();
  EXPECT_LT(ba_err, 5e-3);
  EXPECT_LT(e.tilt_deg, 0.05);
  EXPECT_LT(e.gyro_bias, 1e-4);
  EXPECT_LT(e.velocity, 2e-3);

  // Holding the bias at zero instead tilts gravity by roughly |ba| / G.
  ViAlignmentOptions fixed = options_for(exact);
  fixed.estimate_accel_bias = false;
  const ViAlignmentResult held = align_visual_inertial(w.poses, w.pims, fixed);
  ASSERT_TRUE(held.ok) << held.reason;
  EXPECT_FALSE(held.accel_bias_estimated);
  EXPECT_EQ(held.accel_bias, Eigen::Vector3d::Zero());
  const Errors e_held = errors(held, w, bias);
  EXPECT_GT(e_held.tilt_deg, 5.0 * e.tilt_deg);
  std::cout << "accel bias error " << ba_err << " m/s^2 (sigma " << r.accel_bias_sigma << "), tilt "
            << e.tilt_deg << " deg; with the bias held at 0: tilt " << e_held.tilt_deg << " deg\n";
}

// Driving straight at constant velocity for 2 s: the accel bias looks like a gravity tilt.
struct ConstantVelocityWindow {
  ImuBias bias;
  Noise noise{1.0, 0.001, 0.02 * kDeg};
  Window w;
  ConstantVelocityWindow() {
    UniformMotion motion;
    motion.v_w = {2.0, 0.5, 0.0};
    bias.gyro = {0.01, 0.01, -0.02};
    w = make_window(motion, s_to_ns(0.5), 41, bias, noise, 3);
  }
};

TEST(ViAlignment, ConstantVelocityIsWeakButGivesGravity) {
  const ConstantVelocityWindow cv;
  const Window& w = cv.w;
  const ImuBias& bias = cv.bias;
  const Noise& noise = cv.noise;
  const ViAlignmentResult r = align_visual_inertial(w.poses, w.pims, options_for(noise));
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_TRUE(r.weak_excitation);
  EXPECT_FALSE(r.accel_bias_estimated);
  EXPECT_EQ(r.accel_bias, Eigen::Vector3d::Zero());
  EXPECT_GT(r.accel_bias_sigma, options_for(noise).max_accel_bias_sigma);
  EXPECT_LT(r.gravity_accel_bias_conditioning, 1e-6);
  const Errors e = errors(r, w, bias);
  EXPECT_LT(e.tilt_deg, 0.1);
  EXPECT_LT(e.gyro_bias, 1e-3);
  EXPECT_LT(e.velocity, 0.01);
  std::cout << "constant velocity: ba sigma " << r.accel_bias_sigma << ", conditioning "
            << r.gravity_accel_bias_conditioning << ", tilt " << e.tilt_deg << " deg, velocity "
            << e.velocity << " m/s\n";
}

// The same window with a prior on the accel bias (as a mono rig runs it): the bias is then always
// estimated, the prior holding what the window cannot see near its linearisation value, and
// the gravity stays as good; the window is still reported as weak.
TEST(ViAlignment, AnAccelBiasPriorEstimatesTheBiasWhereTheWindowAloneCannot) {
  const ConstantVelocityWindow cv;
  ViAlignmentOptions options = options_for(cv.noise);
  options.accel_bias_prior_sigma = 0.2;
  const ViAlignmentResult r = align_visual_inertial(cv.w.poses, cv.w.pims, options);
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_TRUE(r.weak_excitation);
  EXPECT_TRUE(r.accel_bias_estimated);
  EXPECT_GT(r.accel_bias_sigma, options.max_accel_bias_sigma) << "the window's own sigma";
  EXPECT_LT(r.accel_bias.norm(), 0.05);
  EXPECT_LT(errors(r, cv.w, cv.bias).tilt_deg, 0.1);
}

TEST(ViAlignment, RotationInPlace) {
  UniformMotion motion;
  motion.omega_b = {0.3, -0.5, 0.8};
  ImuBias bias;
  bias.gyro = {-0.02, 0.0, 0.01};
  const Noise noise{1.0, 0.001, 0.02 * kDeg};
  const Window w = make_window(motion, 0, 41, bias, noise, 5);
  const ViAlignmentResult r = align_visual_inertial(w.poses, w.pims, options_for(noise));
  ASSERT_TRUE(r.ok) << r.reason;
  const Errors e = errors(r, w, bias);
  EXPECT_LT(e.tilt_deg, 0.1);
  EXPECT_LT(e.gyro_bias, 1e-3);
  EXPECT_LT(e.velocity, 0.01);
  std::cout << "rotation in place: tilt " << e.tilt_deg << " deg, gyro bias " << e.gyro_bias
            << " rad/s, velocity " << e.velocity << " m/s, ba estimated " << r.accel_bias_estimated
            << " (sigma " << r.accel_bias_sigma << ")\n";
}

TEST(ViAlignment, LinearisationBiasOfInputDoesNotMatter) {
  const AnalyticMotion motion;
  ImuBias bias;
  bias.gyro = {0.02, -0.015, 0.01};
  const Noise noise{1.0, 0.001, 0.02 * kDeg};
  Window w = make_window(motion, s_to_ns(1.0), 41, bias, noise, 11);
  const ViAlignmentResult a = align_visual_inertial(w.poses, w.pims, options_for(noise));
  ImuBias other;
  other.gyro = {-0.05, 0.04, 0.03};
  for (ImuPreintegration& pim : w.pims) pim.reintegrate(other);
  const ViAlignmentResult b = align_visual_inertial(w.poses, w.pims, options_for(noise));
  ASSERT_TRUE(a.ok && b.ok) << a.reason << b.reason;
  EXPECT_LT((a.gyro_bias - b.gyro_bias).norm(), 1e-9);
  EXPECT_LT((a.g_w - b.g_w).norm(), 1e-9);
  EXPECT_EQ(w.pims.front().bias().gyro, other.gyro);  // the input is left alone
}

const std::string kEuroc = HS_SOURCE_DIR "/../shared/data/euroc";

// Real EuRoC V1_02 flight: ground-truth poses (Vicon) at 20 Hz stand in for stereo vision, in
// the tilted vision world, with the real IMU.
TEST(ViAlignment, RealEurocFlightWithGroundTruthPoses) {
  const std::string gt_path = kEuroc + "/groundtruth/V1_02_medium.csv";
  const std::string imu_path = kEuroc + "/imu/V1_02_medium.csv";
  if (!std::filesystem::exists(gt_path) || !std::filesystem::exists(imu_path)) {
    GTEST_SKIP() << "EuRoC V1_02 ground truth / IMU not found under " << kEuroc;
  }
  const std::vector<NavState> gt = read_ground_truth_csv(gt_path);
  const std::vector<ImuSample> imu = read_imu_csv(imu_path);
  const Eigen::Isometry3d T_v_w = vision_from_world();
  ViAlignmentOptions options;
  options.vision_position_sigma_m = 0.002;
  options.vision_rotation_sigma_rad = 0.02 * kDeg;  // gives rotation chi2/dof ~1
  for (const double start_s : {10.0, 25.0, 40.0, 55.0, 70.0}) {
    const size_t first = static_cast<size_t>(start_s * 200.0);
    ASSERT_LT(first + 400, gt.size());
    Window w;
    for (size_t k = first; k <= first + 400; k += 10) {  // 2 s at 20 Hz
      w.poses.push_back({gt[k].t_ns, T_v_w * gt[k].T_w_b()});
      w.v_v.push_back(T_v_w.linear() * gt[k].v_w);
      if (k > first) {
        w.pims.push_back(preintegrate(imu, gt[k - 10].t_ns, gt[k].t_ns, ImuBias{}));
      }
    }
    const ViAlignmentResult r = align_visual_inertial(w.poses, w.pims, options);
    ASSERT_TRUE(r.ok) << r.reason;
    ImuBias truth;
    truth.gyro = gt[first].gyro_bias;
    const Errors e = errors(r, w, truth);
    // Bounds of the real data: the true accel bias (~0.14 m/s^2) tilts gravity by up to ~0.8 deg
    // when the window cannot estimate it, and the ground-truth biases are estimates themselves.
    EXPECT_LT(e.tilt_deg, 1.2);
    EXPECT_LT(e.gyro_bias, 4e-3);
    EXPECT_LT(e.velocity, 0.08);
    if (r.accel_bias_estimated) {
      EXPECT_LT(e.tilt_deg, 0.6);
      EXPECT_LT((r.accel_bias - gt[first].accel_bias).norm(), 0.15);
    }
    std::cout << "V1_02 at " << start_s << " s: tilt " << e.tilt_deg << " deg (sigma "
              << r.tilt_sigma_rad / kDeg << "), gyro bias error " << e.gyro_bias
              << " rad/s, velocity " << e.velocity << " m/s, accel bias "
              << r.accel_bias.transpose() << " (estimated " << r.accel_bias_estimated << ", sigma "
              << r.accel_bias_sigma << ", truth " << gt[first].accel_bias.transpose()
              << "), chi2/dof " << r.rotation_chi2_per_dof << " " << r.translation_chi2_per_dof
              << "\n";
  }
}

// A mono camera's window: the camera poses (10 cm lever arm from the body) with positions
// `scale` times too small.
std::vector<TimedPose> up_to_scale(const Window& w, const Eigen::Isometry3d& T_b_c, double scale) {
  std::vector<TimedPose> out;
  for (const TimedPose& p : w.poses) {
    Eigen::Isometry3d T_v_c = p.T_w_b * T_b_c;
    T_v_c.translation() /= scale;
    out.push_back({p.t_ns, T_v_c});
  }
  return out;
}

Eigen::Isometry3d camera_extrinsic() {
  Eigen::Isometry3d T_b_c = Eigen::Isometry3d::Identity();
  T_b_c.linear() =
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  T_b_c.translation() = Eigen::Vector3d(-0.02, 0.1, 0.01);
  return T_b_c;
}

// Mono-inertial start (issue 10): 2 s of a moving start seen by a mono camera, positions 3.7
// times too small: the scale comes back with gravity and velocities. Measured over the three
// draws: 3.717, 3.637, 3.747 (+0.5%, -1.7%, +1.3%; sigma 0.035, 0.9%).
// The mono tests' moving start: 2 s from 1.3, 1.6 or 1.9 s (seed 1-3), with a gyro bias.
const Noise kMonoNoise{1.0, 0.001, 0.02 * kDeg};
constexpr double kMonoScale = 3.7;

ImuBias mono_start_bias() {
  ImuBias bias;
  bias.gyro = {0.02, -0.015, 0.01};
  return bias;
}

Window mono_start(unsigned seed) {
  return make_window(AnalyticMotion{}, s_to_ns(1.0 + 0.3 * seed), 41, mono_start_bias(), kMonoNoise,
                     seed);
}

TEST(ViAlignment, UpToScaleMovingStartRecoversTheScale) {
  const ImuBias bias = mono_start_bias();
  const Noise& noise = kMonoNoise;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const Window w = mono_start(seed);
    const ViAlignmentResult r =
        align_visual_inertial_up_to_scale(up_to_scale(w, camera_extrinsic(), kMonoScale),
                                          camera_extrinsic(), w.pims, options_for(noise));
    ASSERT_TRUE(r.ok) << r.reason;
    EXPECT_NEAR(r.scale, kMonoScale, 0.03 * kMonoScale);
    EXPECT_LT(std::abs(r.scale - kMonoScale), 4.0 * r.scale_sigma + 1e-3);
    const Errors e = errors(r, w, bias);
    EXPECT_LT(e.tilt_deg, 0.2);
    EXPECT_LT(e.gyro_bias, 1e-3);
    EXPECT_LT(e.velocity, 0.03);
    std::cout << "up to scale: scale " << r.scale << " +- " << r.scale_sigma << " (truth "
              << kMonoScale << "), tilt " << e.tilt_deg << " deg, velocity " << e.velocity
              << " m/s\n";
  }
}

// The same start seen by vision whose attitudes drift 0.75 deg/s (as a mono odometry's did on
// the real V1_01 flight), taken for gyro bias without an allowance for it. Measured over the
// three draws, scale error without the allowance +2.6 / +2.5 / +4.6%, with it +0.2 / -2.7 /
// +1.3%. The bias the translational equations give is noisy in a 2 s window (errors 0.008 to
// 0.026 rad/s here, against the drift's 0.013): the allowance has a price where nothing drifts
// (the same draws without drift: -0.1 / -2.6 / +1.6% with it, +0.4 / -1.7 / +1.3% without).
TEST(ViAlignment, UpToScaleWithDriftingVisionAttitudes) {
  const ImuBias bias = mono_start_bias();
  const Eigen::Vector3d drift_b(0.0, 0.75 * kDeg, 0.0);
  double error_drifting = 0.0, error_allowed = 0.0;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    Window w = mono_start(seed);
    for (TimedPose& p : w.poses)
      p.T_w_b.linear() *= so3::exp(drift_b * ns_to_s(p.t_ns - w.poses.front().t_ns));
    ViAlignmentOptions options = options_for(kMonoNoise);
    const std::vector<TimedPose> cams = up_to_scale(w, camera_extrinsic(), kMonoScale);
    const ViAlignmentResult drifting =
        align_visual_inertial_up_to_scale(cams, camera_extrinsic(), w.pims, options);
    options.vision_rotation_drift_sigma = 0.02;
    const ViAlignmentResult allowed =
        align_visual_inertial_up_to_scale(cams, camera_extrinsic(), w.pims, options);
    ASSERT_TRUE(drifting.ok) << drifting.reason;
    ASSERT_TRUE(allowed.ok) << allowed.reason;
    EXPECT_NEAR(allowed.scale, kMonoScale, 0.03 * kMonoScale);
    EXPECT_LT((allowed.gyro_bias - bias.gyro).norm(), 0.03);
    error_drifting += std::abs(drifting.scale / kMonoScale - 1.0);
    error_allowed += std::abs(allowed.scale / kMonoScale - 1.0);
    std::cout << "drifting attitudes: scale error " << drifting.scale / kMonoScale - 1
              << ", allowed for " << allowed.scale / kMonoScale - 1 << " +- "
              << allowed.scale_sigma / kMonoScale << "\n";
  }
  EXPECT_LT(error_allowed, 0.7 * error_drifting);
}

// Driving straight at constant speed: no acceleration, no scale. Refused, saying so.
TEST(ViAlignment, UpToScaleAtConstantVelocityIsRefusedForLackOfAcceleration) {
  UniformMotion motion;
  motion.v_w = {2.0, 0.5, 0.0};
  const Noise noise{1.0, 0.001, 0.02 * kDeg};
  const Window w = make_window(motion, s_to_ns(0.5), 41, ImuBias{}, noise, 3);
  const ViAlignmentResult r = align_visual_inertial_up_to_scale(
      up_to_scale(w, camera_extrinsic(), 2.0), camera_extrinsic(), w.pims, options_for(noise));
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("not enough acceleration"), std::string::npos) << r.reason;
}

// Real V1_02 motion (ground-truth camera poses made up to scale, real IMU with its accel bias):
// the scale of 4 s windows of the flight. Measured: +0.1%, +0.7%, -4.0%, +0.1%, -1.3%; 2 s
// windows gave -6.5% to +2.0% (the accel bias, 0.14 m/s^2, is not separable in most of them),
// 6 s windows within 1.5%.
TEST(ViAlignment, UpToScaleRealEurocFlightRecoversTheScale) {
  const std::string gt_path = kEuroc + "/groundtruth/V1_02_medium.csv";
  const std::string imu_path = kEuroc + "/imu/V1_02_medium.csv";
  if (!std::filesystem::exists(gt_path) || !std::filesystem::exists(imu_path))
    GTEST_SKIP() << "EuRoC V1_02 ground truth / IMU not found under " << kEuroc;
  const std::vector<NavState> gt = read_ground_truth_csv(gt_path);
  const std::vector<ImuSample> imu = read_imu_csv(imu_path);
  ViAlignmentOptions options;
  options.vision_position_sigma_m = 0.002;
  options.vision_rotation_sigma_rad = 0.02 * kDeg;
  constexpr double kScale = 2.5;
  constexpr size_t kWindow = 800;  // 4 s of 200 Hz ground truth
  int solved = 0;
  for (const double start_s : {10.0, 25.0, 40.0, 55.0, 70.0}) {
    const size_t first = static_cast<size_t>(start_s * 200.0);
    Window w;
    for (size_t k = first; k <= first + kWindow; k += 10) {
      w.poses.push_back({gt[k].t_ns, gt[k].T_w_b()});
      if (k > first) w.pims.push_back(preintegrate(imu, gt[k - 10].t_ns, gt[k].t_ns, ImuBias{}));
    }
    const ViAlignmentResult r = align_visual_inertial_up_to_scale(
        up_to_scale(w, camera_extrinsic(), kScale), camera_extrinsic(), w.pims, options);
    std::cout << "V1_02 up to scale at " << start_s << " s: "
              << (r.ok ? "scale " + std::to_string(r.scale) + " +- " + std::to_string(r.scale_sigma)
                       : r.reason)
              << " (truth " << kScale << ")\n";
    if (!r.ok) continue;
    ++solved;
    EXPECT_NEAR(r.scale, kScale, 0.05 * kScale) << start_s << " s";
  }
  EXPECT_GE(solved, 3);
}

// The real flying frames of V1_01 (issue 10's mono target), ground-truth camera poses made up to
// scale with the real IMU and the mono options: what the IMU can tell of the scale with perfect
// vision. Measured from the first frame (285.26 s) at 0.2 s spacing: to frame 52 (2.6 s) refused,
// scale -2.6% +- 5.6%; to frame 64 (3.2 s) -2.4% +- 4.7%; from 1 s earlier (IMU only, no images
// there) to frame 52: -2.8% +- 2.6%. The tracker's own start at frame 52 rests on vision poses
// and comes out further off (see MonoAccuracy).
TEST(ViAlignment, UpToScaleRealV1_01FlightStart) {
  const std::string dir = kEuroc + "/V1_01_flight_cam0/mav0";
  if (!std::filesystem::exists(dir))
    GTEST_SKIP() << "EuRoC V1_01_flight_cam0 not found under " << kEuroc;
  const std::vector<NavState> gt =
      read_ground_truth_csv(dir + "/state_groundtruth_estimate0/data.csv");
  const std::vector<ImuSample> imu = read_imu_csv(dir + "/imu0/data.csv");
  ViAlignmentOptions options;  // as MonoOptions::alignment
  options.max_accel_bias_sigma = 0.05;
  options.accel_bias_prior_sigma = 0.2;
  constexpr double kScale = 2.0;
  constexpr int64_t kFirstFrameNs = 1403715285262142976;
  // `drift_b`: the vision attitudes turn away from the truth at this body rate (rad/s).
  const auto align = [&](int64_t t0_ns, int64_t t1_ns,
                         const Eigen::Vector3d& drift_b = Eigen::Vector3d::Zero()) {
    Window w;
    int64_t prev_ns = 0;
    for (const NavState& s : gt) {
      if (s.t_ns < t0_ns - 10'000'000 || s.t_ns > t1_ns + 10'000'000) continue;
      if (!w.poses.empty() && s.t_ns - prev_ns < 190'000'000) continue;
      Eigen::Isometry3d T_w_b = s.T_w_b();
      T_w_b.linear() *= so3::exp(drift_b * ns_to_s(s.t_ns - t0_ns));
      w.poses.push_back({s.t_ns, T_w_b});
      if (w.poses.size() > 1) w.pims.push_back(preintegrate(imu, prev_ns, s.t_ns, ImuBias{}));
      prev_ns = s.t_ns;
    }
    return align_visual_inertial_up_to_scale(up_to_scale(w, camera_extrinsic(), kScale),
                                             camera_extrinsic(), w.pims, options);
  };
  const int64_t frame52_ns = kFirstFrameNs + 52 * int64_t{50'000'000};
  const ViAlignmentResult to52 = align(kFirstFrameNs, frame52_ns);
  EXPECT_FALSE(to52.ok);
  EXPECT_NE(to52.reason.find("not enough acceleration"), std::string::npos) << to52.reason;
  const ViAlignmentResult to64 = align(kFirstFrameNs, kFirstFrameNs + 64 * int64_t{50'000'000});
  ASSERT_TRUE(to64.ok) << to64.reason;
  EXPECT_NEAR(to64.scale, kScale, 0.05 * kScale);
  const ViAlignmentResult earlier = align(kFirstFrameNs - 1'000'000'000, frame52_ns);
  ASSERT_TRUE(earlier.ok) << earlier.reason;
  EXPECT_NEAR(earlier.scale, kScale, 0.05 * kScale);
  std::cout << "V1_01 flight, perfect vision: to frame 52 " << to52.reason << "; to frame 64 "
            << to64.scale / kScale - 1 << " +- " << to64.scale_sigma / kScale
            << "; 1 s earlier to frame 52 " << earlier.scale / kScale - 1 << " +- "
            << earlier.scale_sigma / kScale << "\n";

  // The mono odometry's attitudes drift 0.75 deg/s, mostly in pitch (body y), over this start
  // (measured against the gyro and the ground truth). Taken for gyro bias, the drift tilts
  // gravity through the window: measured, scale +9.4% off without the allowance for it, -2.1%
  // with it (gyro bias y 0.0095 and 0.0280 rad/s, truth 0.0217).
  const Eigen::Vector3d drift_b(0.0, 0.75 * kDeg, 0.05 * kDeg);
  const int64_t frame64_ns = kFirstFrameNs + 64 * int64_t{50'000'000};
  const ViAlignmentResult drifting = align(kFirstFrameNs, frame64_ns, drift_b);
  options.vision_rotation_drift_sigma = 0.02;
  const ViAlignmentResult allowed = align(kFirstFrameNs, frame64_ns, drift_b);
  ASSERT_TRUE(drifting.ok) << drifting.reason;
  ASSERT_TRUE(allowed.ok) << allowed.reason;
  EXPECT_GT(std::abs(drifting.scale / kScale - 1.0), 0.08);
  EXPECT_NEAR(allowed.scale, kScale, 0.05 * kScale);
  const double true_bg_y = gt.front().gyro_bias.y();
  EXPECT_LT(std::abs(allowed.gyro_bias.y() - true_bg_y), 0.008);
  EXPECT_GT(std::abs(drifting.gyro_bias.y() - true_bg_y), 0.01);
  std::cout << "V1_01 flight, attitudes drifting 0.75 deg/s: scale " << drifting.scale / kScale - 1
            << " (gyro bias " << drifting.gyro_bias.transpose()
            << "), allowed for: " << allowed.scale / kScale - 1 << " +- "
            << allowed.scale_sigma / kScale << " (gyro bias " << allowed.gyro_bias.transpose()
            << ", truth " << gt.front().gyro_bias.transpose() << ")\n";
}

TEST(ViAlignment, RefusesDegenerateInput) {
  const AnalyticMotion motion;
  const Noise noise{1.0, 0.001, 0.02 * kDeg};
  const Window good = make_window(motion, s_to_ns(1.0), 6, ImuBias{}, noise, 2);
  ASSERT_TRUE(align_visual_inertial(good.poses, good.pims).ok);
  const auto refused = [](const Window& w, const std::string& expected) {
    const ViAlignmentResult r = align_visual_inertial(w.poses, w.pims);
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.reason.find(expected), std::string::npos) << r.reason;
  };

  Window two = good;
  two.poses.resize(2);
  two.pims.erase(two.pims.begin() + 1, two.pims.end());
  refused(two, "at least 3 poses");

  Window missing = good;
  missing.pims.pop_back();
  refused(missing, "one preintegration per");

  Window nan_pose = good;
  nan_pose.poses[3].T_w_b.translation().x() = std::numeric_limits<double>::quiet_NaN();
  refused(nan_pose, "pose 3 is not finite");

  Window not_rotation = good;
  not_rotation.poses[2].T_w_b.linear() *= 1.1;
  refused(not_rotation, "pose 2 rotation");

  Window empty = good;
  empty.pims[1] = preintegrate({}, good.poses[1].t_ns, good.poses[2].t_ns, ImuBias{});
  refused(empty, "preintegration 1 is empty");

  Window shifted = good;
  shifted.pims[2] = shifted.pims[3];
  refused(shifted, "preintegration 2 covers");

  // Every sample of one interval dropped: the preintegration holds across a 50 ms gap.
  const int64_t t0 = good.poses[0].t_ns, t1 = good.poses.back().t_ns;
  std::vector<ImuSample> gappy = motion.samples(t0 - 10'000'000, t1 + 10'000'000, 5'000'000);
  Window gap = good;
  gappy.erase(std::remove_if(gappy.begin(), gappy.end(),
                             [&](const ImuSample& s) {
                               return s.t_ns > good.poses[2].t_ns && s.t_ns < good.poses[3].t_ns;
                             }),
              gappy.end());
  gap.pims[2] = preintegrate(gappy, good.poses[2].t_ns, good.poses[3].t_ns, ImuBias{});
  refused(gap, "preintegration 2 has an IMU gap");

  Window nan_imu = good;
  std::vector<ImuSample> bad = motion.samples(t0 - 10'000'000, t1 + 10'000'000, 5'000'000);
  for (ImuSample& s : bad) s.accel.x() = std::numeric_limits<double>::quiet_NaN();
  nan_imu.pims[0] = preintegrate(bad, good.poses[0].t_ns, good.poses[1].t_ns, ImuBias{});
  refused(nan_imu, "preintegration 0");

  // A rotation drift the IMU does not see makes the gyro bias implausible.
  Window spinning = good;
  for (size_t i = 0; i < spinning.poses.size(); ++i) {
    spinning.poses[i].T_w_b.linear() =
        spinning.poses[i].T_w_b.linear() * so3::exp(Eigen::Vector3d(0.0, 0.0, 0.05 * i));
  }
  refused(spinning, "gyro bias estimate");
}

}  // namespace
}  // namespace hs
