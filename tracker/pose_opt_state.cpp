#include "tracker/pose_opt_state.h"

#include "common/imu/so3.h"

namespace hs {

BodyState BodyState::from(const NavState& s) {
  BodyState b;
  b.R_w_b = s.q_w_b.normalized().toRotationMatrix();
  b.p_w_b = s.p_w_b;
  b.v_w = s.v_w;
  b.bias = {s.gyro_bias, s.accel_bias};
  return b;
}

NavState BodyState::to_nav_state(const NavState& like) const {
  NavState s = like;
  s.q_w_b = Eigen::Quaterniond(R_w_b).normalized();
  s.p_w_b = p_w_b;
  s.v_w = v_w;
  s.gyro_bias = bias.gyro;
  s.accel_bias = bias.accel;
  return s;
}

BodyState BodyState::retracted(const Vector15d& delta) const {
  BodyState b = retracted_pose(delta.head<6>());
  b.v_w += delta.segment<3>(6);
  b.bias.gyro += delta.segment<3>(9);
  b.bias.accel += delta.segment<3>(12);
  return b;
}

BodyState BodyState::retracted_pose(const Eigen::Matrix<double, 6, 1>& delta) const {
  BodyState b = *this;
  b.R_w_b = R_w_b * so3::exp(delta.head<3>());
  b.p_w_b += delta.tail<3>();
  return b;
}

bool BodyState::all_finite() const {
  return R_w_b.allFinite() && p_w_b.allFinite() && v_w.allFinite() && bias.gyro.allFinite() &&
         bias.accel.allFinite();
}

}  // namespace hs
