#include "common/imu/imu_residual.h"

#include "common/imu/so3.h"

namespace hs {

NavState predict(const NavState& state_i, const ImuPreintegration& pim,
                 const Eigen::Vector3d& g_w) {
  const ImuDelta d = pim.corrected(ImuBias{state_i.gyro_bias, state_i.accel_bias});
  const double dt = pim.dt_s();
  const Eigen::Matrix3d R_i = state_i.q_w_b.toRotationMatrix();
  NavState s = state_i;
  s.t_ns = state_i.t_ns + (pim.t1_ns() - pim.t0_ns());
  s.q_w_b = Eigen::Quaterniond(R_i * d.R).normalized();
  s.v_w = state_i.v_w + g_w * dt + R_i * d.v;
  s.p_w_b = state_i.p_w_b + state_i.v_w * dt + 0.5 * dt * dt * g_w + R_i * d.p;
  return s;
}

Vector9d imu_residual(const ImuPreintegration& pim, const Eigen::Matrix3d& R_w_bi,
                      const Eigen::Vector3d& p_w_bi, const Eigen::Vector3d& v_w_i,
                      const Eigen::Matrix3d& R_w_bj, const Eigen::Vector3d& p_w_bj,
                      const Eigen::Vector3d& v_w_j, const ImuBias& bias_i,
                      const Eigen::Vector3d& g_w, ImuResidualJacobians* jacobians) {
  const Eigen::Vector3d dbg = bias_i.gyro - pim.bias().gyro;
  const ImuDelta d = pim.corrected(dbg, bias_i.accel - pim.bias().accel);
  const double dt = pim.dt_s();
  const Eigen::Matrix3d Rt_i = R_w_bi.transpose();
  const Eigen::Vector3d dv_w = v_w_j - v_w_i - g_w * dt;
  const Eigen::Vector3d dp_w = p_w_bj - p_w_bi - v_w_i * dt - 0.5 * dt * dt * g_w;

  Vector9d r;
  const Eigen::Vector3d r_R = so3::log(d.R.transpose() * Rt_i * R_w_bj);
  r.segment<3>(0) = r_R;
  r.segment<3>(3) = Rt_i * dv_w - d.v;
  r.segment<3>(6) = Rt_i * dp_w - d.p;
  if (jacobians == nullptr) return r;

  ImuResidualJacobians& J = *jacobians;
  const Eigen::Matrix3d Jr_inv = so3::right_jacobian_inverse(r_R);
  const Eigen::Matrix3d Z = Eigen::Matrix3d::Zero();
  J.R_i << -Jr_inv * R_w_bj.transpose() * R_w_bi, so3::hat(Rt_i * dv_w), so3::hat(Rt_i * dp_w);
  J.p_i << Z, Z, -Rt_i;
  J.v_i << Z, -Rt_i, -dt * Rt_i;
  J.R_j << Jr_inv, Z, Z;
  J.p_j << Z, Z, Rt_i;
  J.v_j << Z, Rt_i, Z;
  J.bg << -Jr_inv * so3::exp(r_R).transpose() * so3::right_jacobian(pim.dR_dbg() * dbg) *
              pim.dR_dbg(),
      -pim.dv_dbg(), -pim.dp_dbg();
  J.ba << Z, -pim.dv_dba(), -pim.dp_dba();
  return r;
}

}  // namespace hs
