#pragma once
// Pose-graph optimisation for loop correction (issue 7): keyframe poses linked by relative-pose
// edges (the odometry chain and strong covisibility, as estimated before the loop; the loops as
// measured). With gravity known only x, y, z and yaw of each pose move (4-DoF): roll and pitch
// are observed by the IMU and do not drift; without it all 6 DoF do.
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <vector>

namespace hs {

struct PoseGraphOptions {
  bool four_dof = true;  // false: 6-DoF (no gravity)
  int max_iterations = 50;
  double sigma_m = 0.01;     // per edge, translation
  double sigma_rad = 0.002;  // per edge, rotation
};

struct PoseGraphEdge {
  int64_t from = -1, to = -1;
  Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();
  double weight = 1.0;  // scales the information (loops and strong links weigh more)
};

struct PoseGraphResult {
  std::map<int64_t, Eigen::Isometry3d> T_w_b;
  int iterations = 0;
  double initial_cost = 0.0, final_cost = 0.0;
  double time_ms = 0.0;
};

// Optimises every pose but `fixed`'s. Edges naming an absent pose are an error.
PoseGraphResult optimise_pose_graph(const std::map<int64_t, Eigen::Isometry3d>& T_w_b,
                                    const std::vector<PoseGraphEdge>& edges, int64_t fixed,
                                    const PoseGraphOptions& options);

}  // namespace hs
