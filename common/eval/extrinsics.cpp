#include "common/eval/extrinsics.h"

#include <cmath>

#include "common/calib/camera_calib.h"
#include "common/core/error.h"

namespace hs {

Eigen::Isometry3d T_b_c_from_values(const std::vector<double>& values, const std::string& source) {
  if (values.size() != 16)
    throw InputError(source, "T_b_c needs 16 numbers, found " + std::to_string(values.size()));
  Eigen::Matrix4d M;
  for (int i = 0; i < 16; ++i) M(i / 4, i % 4) = values[i];
  for (double v : values)
    if (!std::isfinite(v)) throw InputError(source, "T_b_c has a non-finite entry");
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  constexpr double kTol = 1e-6;
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > kTol ||
      std::abs(R.determinant() - 1.0) > kTol)
    throw InputError(source, "T_b_c rotation is not orthonormal");
  if ((M.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > kTol)
    throw InputError(source, "T_b_c last row must be 0 0 0 1");
  Eigen::Isometry3d T_b_c = Eigen::Isometry3d::Identity();
  // Re-orthonormalise so the printed 1e-12 digits of a calibration file do not accumulate.
  T_b_c.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  T_b_c.translation() = M.topRightCorner<3, 1>();
  return T_b_c;
}

Eigen::Isometry3d load_T_b_c_yaml(const std::string& path) {
  return read_camera_yaml(path).T_b_c;
}

Eigen::Isometry3d parse_T_b_c(const std::vector<std::string>& args) {
  if (args.size() == 1) return load_T_b_c_yaml(args[0]);
  std::vector<double> values;
  for (const std::string& a : args) {
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(a, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != a.size()) throw InputError("--T-b-c", "not a number: '" + a + "'");
    values.push_back(v);
  }
  return T_b_c_from_values(values, "--T-b-c");
}

}  // namespace hs
