#include "common/imu/static_init.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "common/dataset/euroc_csv.h"
#include "common/imu/so3.h"
#include "tests/imu/analytic_motion.h"

namespace hs {
namespace {

const std::string kStatic = HS_SOURCE_DIR "/../shared/data/euroc/V1_01_static_stereo/mav0";

double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / 3.14159265358979323846;
}

TEST(ImuStaticInit, RealEurocStaticWindow) {
  const std::string imu_path = kStatic + "/imu0/data.csv";
  const std::string gt_path = kStatic + "/state_groundtruth_estimate0/data.csv";
  if (!std::filesystem::exists(imu_path) || !std::filesystem::exists(gt_path)) {
    GTEST_SKIP() << "EuRoC static sample not found under " << kStatic;
  }
  // Ground truth: orientation and gyro bias at the start, and the span it covers (the MAV sits
  // on the ground with its motors running; the IMU file goes on for a second after it).
  const std::vector<NavState> gt = read_ground_truth_csv(gt_path);
  ASSERT_FALSE(gt.empty());
  const int64_t gt_begin = gt.front().t_ns, gt_end = gt.back().t_ns;
  const Eigen::Quaterniond q_w_b = gt.front().q_w_b;
  const Eigen::Vector3d bw = gt.front().gyro_bias;

  std::vector<ImuSample> window;
  for (const ImuSample& s : read_imu_csv(imu_path)) {
    if (s.t_ns >= gt_begin && s.t_ns <= gt_end) window.push_back(s);
  }
  ASSERT_GT(window.size(), 900u);
  const StaticInitResult r = initialise_from_static(window);
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_TRUE(r.reason.empty());

  const double err_deg = angle_deg(q_w_b.normalized() * r.gravity_dir_b, -Eigen::Vector3d::UnitZ());
  EXPECT_LT(err_deg, 1.0);
  EXPECT_LT((r.gyro_bias - bw).cwiseAbs().maxCoeff(), 0.005) << r.gyro_bias.transpose();
  // The yaw-free attitude maps the measured gravity onto world down.
  EXPECT_LT((r.q_w_b * r.gravity_dir_b + Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  EXPECT_NEAR(r.accel_norm_mean, 9.81, 0.3);
  std::cout << "gravity direction error " << err_deg << " deg, gyro bias error "
            << (r.gyro_bias - bw).transpose() << " rad/s, block |a| std " << r.accel_norm_std
            << ", block gyro std " << r.gyro_std.transpose() << "\n";

  // Sample-to-sample statistics (one-sample blocks) see the motor vibration, which is why the
  // check works on block means.
  ImuOptions per_sample;
  per_sample.static_block_ns = 1;
  const StaticInitResult raw = initialise_from_static(window, per_sample);
  EXPECT_FALSE(raw.ok);
  EXPECT_GT(raw.accel_norm_std, 3.0 * r.accel_norm_std);
}

TEST(ImuStaticInit, SyntheticTiltedBody) {
  // Exact static samples of a tilted body with a gyro bias.
  const Eigen::Matrix3d R_w_b = so3::exp(Eigen::Vector3d(0.3, -0.5, 1.2));
  const Eigen::Vector3d bg(0.01, -0.02, 0.003);
  std::vector<ImuSample> window;
  for (int k = 0; k < 300; ++k) {
    ImuSample s;
    s.t_ns = k * 5'000'000LL;
    s.gyro = bg;
    s.accel = R_w_b.transpose() * Eigen::Vector3d(0, 0, 9.81);
    window.push_back(s);
  }
  window[17].accel.x() = std::numeric_limits<double>::quiet_NaN();  // ignored
  const StaticInitResult r = initialise_from_static(window);
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_EQ(r.samples_used, 299);
  EXPECT_LT(angle_deg(R_w_b * r.gravity_dir_b, -Eigen::Vector3d::UnitZ()), 1e-9);
  EXPECT_LT((r.gyro_bias - bg).norm(), 1e-15);
  // Same roll and pitch: q_w_b differs from R_w_b by a rotation about world z only.
  const Eigen::Matrix3d yaw_only = R_w_b * r.q_w_b.toRotationMatrix().transpose();
  EXPECT_LT((yaw_only * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  const Eigen::Vector3d euler = r.q_w_b.toRotationMatrix().eulerAngles(2, 1, 0);  // yaw pitch roll
  EXPECT_NEAR(std::sin(euler[0]), 0.0, 1e-12);
}

TEST(ImuStaticInit, MovingWindowIsRejected) {
  const test::AnalyticMotion motion;
  const StaticInitResult r = initialise_from_static(motion.samples(0, s_to_ns(2.0), 5'000'000));
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("exceeds"), std::string::npos) << r.reason;
}

TEST(ImuStaticInit, RotatingInPlaceIsRejectedByGyro) {
  // Constant specific force (no linear acceleration) but a varying rate.
  std::vector<ImuSample> window;
  for (int k = 0; k < 400; ++k) {
    ImuSample s;
    s.t_ns = k * 5'000'000LL;
    s.gyro = Eigen::Vector3d(0, 0, 0.3 * std::sin(0.05 * k));
    s.accel = Eigen::Vector3d(0, 0, 9.81);
    window.push_back(s);
  }
  const StaticInitResult r = initialise_from_static(window);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("gyro std"), std::string::npos) << r.reason;
}

TEST(ImuStaticInit, ShortOrEmptyWindowIsRejected) {
  std::vector<ImuSample> window(150);  // 0.745 s at 200 Hz
  for (size_t k = 0; k < window.size(); ++k) {
    window[k].t_ns = static_cast<int64_t>(k) * 5'000'000LL;
    window[k].accel = Eigen::Vector3d(0, 0, 9.81);
  }
  StaticInitResult r = initialise_from_static(window);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("shorter than"), std::string::npos) << r.reason;
  EXPECT_LT((r.gravity_dir_b + Eigen::Vector3d::UnitZ()).norm(), 1e-15);  // still estimated
  r = initialise_from_static({});
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.reason.empty());
}

}  // namespace
}  // namespace hs
