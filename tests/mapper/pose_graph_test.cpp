// Pose-graph loop correction on a drifting square drive: odometry edges carry a yaw and scale
// drift, one loop edge the truth; the optimised poses close the loop, and 4-DoF keeps every
// pose's roll and pitch.
#include "mapper/pose_graph.h"

#include <gtest/gtest.h>

namespace hs {
namespace {

Eigen::Isometry3d pose(double x, double y, double yaw, double roll = 0.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, 1.5);
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return T;
}

struct Square {
  std::vector<Eigen::Isometry3d> truth, drifted;
  std::vector<PoseGraphEdge> edges;
};

// 80 poses round a 20 m square, each with a small roll; odometry turns 0.05 deg too much and
// goes 0.5% too far per step. The last pose sees the first (loop edge, true).
Square square() {
  Square s;
  for (int k = 0; k < 80; ++k) {
    const int side = k / 20;
    const double a = (k % 20) / 20.0 * 20.0;
    const double xs[4] = {a, 20, 20 - a, 0}, ys[4] = {0, a, 20, 20 - a};
    s.truth.push_back(pose(xs[side], ys[side], side * M_PI / 2, 0.01 * (k % 3)));
  }
  s.drifted.push_back(s.truth[0]);
  for (size_t k = 1; k < s.truth.size(); ++k) {
    Eigen::Isometry3d step = s.truth[k - 1].inverse() * s.truth[k];
    step.translation() *= 1.005;
    step.linear() = Eigen::AngleAxisd(0.05 * M_PI / 180, Eigen::Vector3d::UnitZ()) * step.linear();
    // Gravity is observed: the drifted pose keeps the true roll (yaw and position drift only).
    Eigen::Isometry3d next = s.drifted.back() * step;
    const double yaw = std::atan2(next.linear()(1, 0), next.linear()(0, 0));
    next.linear() = pose(0, 0, yaw, 0.01 * (k % 3)).linear();
    s.drifted.push_back(next);
    s.edges.push_back({static_cast<int64_t>(k - 1), static_cast<int64_t>(k),
                       s.drifted[k - 1].inverse() * next, 1.0});
  }
  s.edges.push_back({0, 79, s.truth[0].inverse() * s.truth[79], 1.0});
  return s;
}

std::map<int64_t, Eigen::Isometry3d> as_map(const std::vector<Eigen::Isometry3d>& poses) {
  std::map<int64_t, Eigen::Isometry3d> m;
  for (size_t k = 0; k < poses.size(); ++k) m[static_cast<int64_t>(k)] = poses[k];
  return m;
}

double max_error_m(const std::map<int64_t, Eigen::Isometry3d>& est,
                   const std::vector<Eigen::Isometry3d>& truth) {
  double e = 0;
  for (const auto& [k, T] : est)
    e = std::max(e, (T.translation() - truth[static_cast<size_t>(k)].translation()).norm());
  return e;
}

TEST(PoseGraph, FourDofClosesTheLoopAndKeepsRollAndPitch) {
  const Square s = square();
  const double before = max_error_m(as_map(s.drifted), s.truth);
  const PoseGraphResult r = optimise_pose_graph(as_map(s.drifted), s.edges, 0, {});
  const double after = max_error_m(r.T_w_b, s.truth);
  EXPECT_GT(before, 0.5);
  EXPECT_LT(after, 0.15 * before) << "before " << before << " m";
  EXPECT_LT((r.T_w_b.at(79).translation() - s.truth[79].translation()).norm(), 0.05);
  EXPECT_LT(r.final_cost, 0.01 * r.initial_cost);
  EXPECT_TRUE(r.T_w_b.at(0).isApprox(s.drifted[0]));  // held
  for (const auto& [k, T] : r.T_w_b) {
    const Eigen::Vector3d up = T.linear().transpose() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d up0 =
        s.drifted[static_cast<size_t>(k)].linear().transpose() * Eigen::Vector3d::UnitZ();
    EXPECT_LT((up - up0).norm(), 1e-9) << "pose " << k;
  }
}

TEST(PoseGraph, SixDofClosesTheLoopToo) {
  const Square s = square();
  PoseGraphOptions options;
  options.four_dof = false;
  const PoseGraphResult r = optimise_pose_graph(as_map(s.drifted), s.edges, 0, options);
  EXPECT_LT(max_error_m(r.T_w_b, s.truth), 0.15 * max_error_m(as_map(s.drifted), s.truth));
}

TEST(PoseGraph, AnEdgeToAnAbsentPoseIsAnError) {
  EXPECT_THROW(optimise_pose_graph({{0, Eigen::Isometry3d::Identity()}},
                                   {{0, 7, Eigen::Isometry3d::Identity(), 1.0}}, 0, {}),
               std::invalid_argument);
}

}  // namespace
}  // namespace hs
