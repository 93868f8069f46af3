#include "mapper/pose_manifold.h"

#include "common/imu/so3.h"

namespace hs {
namespace {

Eigen::Map<Eigen::Quaterniond> q_of(double* pose) {
  return Eigen::Map<Eigen::Quaterniond>(pose);
}
Eigen::Map<Eigen::Vector3d> vec3_at(double* data) {
  return Eigen::Map<Eigen::Vector3d>(data);
}

// The selection matrix between the pose block's ambient and tangent layouts, row-major
// Rows x Cols (7 x 6 for Plus, 6 x 7 for Minus).
template <int Rows, int Cols>
void selection(double* out) {
  Eigen::Map<Eigen::Matrix<double, Rows, Cols, Eigen::RowMajor>> J(out);
  J.setZero();
  J.template topLeftCorner<3, 3>().setIdentity();
  J.template bottomRightCorner<3, 3>().setIdentity();
}

}  // namespace

bool PoseManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  const Eigen::Map<const Eigen::Vector3d> d_phi(delta), d_p(delta + 3);
  q_of(x_plus_delta) = (pose_q_w_b(x) * so3::exp_quat(d_phi)).normalized();
  vec3_at(x_plus_delta + 4) = pose_p_w_b(x) + d_p;
  return true;
}

bool PoseManifold::PlusJacobian(const double* /*x*/, double* jacobian) const {
  selection<kPoseSize, kPoseTangentSize>(jacobian);
  return true;
}

bool PoseManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  vec3_at(y_minus_x) = so3::log(pose_q_w_b(x).inverse() * pose_q_w_b(y));
  vec3_at(y_minus_x + 3) = pose_p_w_b(y) - pose_p_w_b(x);
  return true;
}

bool PoseManifold::MinusJacobian(const double* /*x*/, double* jacobian) const {
  selection<kPoseTangentSize, kPoseSize>(jacobian);
  return true;
}

void state_to_blocks(const NavState& state, double* pose, double* speed_bias) {
  q_of(pose) = state.q_w_b.normalized();
  vec3_at(pose + 4) = state.p_w_b;
  vec3_at(speed_bias) = state.v_w;
  vec3_at(speed_bias + 3) = state.gyro_bias;
  vec3_at(speed_bias + 6) = state.accel_bias;
}

void blocks_to_state(const double* pose, const double* speed_bias, NavState* state) {
  state->q_w_b = pose_q_w_b(pose).normalized();
  state->p_w_b = pose_p_w_b(pose);
  state->v_w = Eigen::Map<const Eigen::Vector3d>(speed_bias);
  state->gyro_bias = Eigen::Map<const Eigen::Vector3d>(speed_bias + 3);
  state->accel_bias = Eigen::Map<const Eigen::Vector3d>(speed_bias + 6);
}

}  // namespace hs
