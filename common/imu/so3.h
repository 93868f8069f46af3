#pragma once
// SO(3) helpers on Eigen types: hat/vee, exponential and logarithm maps, and the right Jacobian
// with its inverse. Perturbations are on the right: R * Exp(delta). The small-angle branches use
// Taylor series so that every function is smooth and accurate down to (and including) zero, and
// log() stays accurate at angles near pi.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hs::so3 {

// Skew-symmetric matrix with hat(w) * x == w.cross(x).
Eigen::Matrix3d hat(const Eigen::Vector3d& w);
// Inverse of hat(), reading the skew-symmetric part of `W`.
Eigen::Vector3d vee(const Eigen::Matrix3d& W);

Eigen::Matrix3d exp(const Eigen::Vector3d& phi);
Eigen::Quaterniond exp_quat(const Eigen::Vector3d& phi);

// Rotation vector with angle in [0, pi].
Eigen::Vector3d log(const Eigen::Quaterniond& q);
Eigen::Vector3d log(const Eigen::Matrix3d& R);  // R must be a rotation matrix

// Exp(phi + d) ~= Exp(phi) * Exp(right_jacobian(phi) * d) for small d.
Eigen::Matrix3d right_jacobian(const Eigen::Vector3d& phi);
// Log(Exp(phi) * Exp(d)) ~= phi + right_jacobian_inverse(phi) * d; defined for |phi| < 2 pi.
Eigen::Matrix3d right_jacobian_inverse(const Eigen::Vector3d& phi);

}  // namespace hs::so3
