#include "common/dataset/euroc_csv.h"

#include <cmath>

#include "common/core/csv.h"
#include "common/core/error.h"

namespace hs {
namespace {

// Rows of one EuRoC file: exact column count and strictly increasing timestamps.
class EurocRows {
 public:
  EurocRows(const std::string& path, size_t columns) : csv_(path), columns_(columns) {}

  // Next row with its timestamp in column 0; false at end of file.
  bool next(CsvRow& row, int64_t& t_ns) {
    if (!csv_.next(row)) return false;
    if (row.fields.size() != columns_)
      throw InputError(csv_.path(), row.line,
                       "expected " + std::to_string(columns_) + " comma-separated fields, found " +
                           std::to_string(row.fields.size()));
    t_ns = csv_.int64_at(row, 0);
    if (prev_line_ > 0 && t_ns <= prev_t_ns_)
      throw InputError(csv_.path(), row.line,
                       std::string(t_ns == prev_t_ns_ ? "duplicate" : "decreasing") +
                           " timestamp " + std::to_string(t_ns) + " (previous " +
                           std::to_string(prev_t_ns_) + " at line " + std::to_string(prev_line_) +
                           ")");
    prev_t_ns_ = t_ns;
    prev_line_ = row.line;
    return true;
  }

  double scalar(const CsvRow& row, size_t i) const { return csv_.double_at(row, i); }
  Eigen::Vector3d vec3(const CsvRow& row, size_t first) const {
    return {csv_.double_at(row, first), csv_.double_at(row, first + 1),
            csv_.double_at(row, first + 2)};
  }
  const std::string& path() const { return csv_.path(); }

 private:
  CsvReader csv_;
  size_t columns_;
  int64_t prev_t_ns_ = 0;
  long prev_line_ = 0;
};

}  // namespace

std::vector<ImageEntry> read_camera_csv(const std::string& cam_dir) {
  EurocRows rows(cam_dir + "/data.csv", 2);
  std::vector<ImageEntry> entries;
  CsvRow row;
  int64_t t_ns = 0;
  while (rows.next(row, t_ns)) {
    const std::string& name = row.fields[1];
    if (name.empty()) throw InputError(rows.path(), row.line, "empty image file name");
    entries.push_back({t_ns, cam_dir + "/data/" + name, row.line});
  }
  return entries;
}

std::vector<ImuSample> read_imu_csv(const std::string& path) {
  EurocRows rows(path, 7);
  std::vector<ImuSample> samples;
  CsvRow row;
  ImuSample s;
  while (rows.next(row, s.t_ns)) {
    s.gyro = rows.vec3(row, 1);
    s.accel = rows.vec3(row, 4);
    samples.push_back(s);
  }
  return samples;
}

std::vector<NavState> read_ground_truth_csv(const std::string& path) {
  EurocRows rows(path, 17);
  std::vector<NavState> states;
  CsvRow row;
  NavState x;
  while (rows.next(row, x.t_ns)) {
    x.p_w_b = rows.vec3(row, 1);
    const Eigen::Vector3d q_xyz = rows.vec3(row, 5);
    const Eigen::Quaterniond q(rows.scalar(row, 4), q_xyz.x(), q_xyz.y(), q_xyz.z());
    // EuRoC prints 6 digits, so |q| is 1 to ~1e-6; anything far off is corrupt data.
    if (std::abs(q.norm() - 1.0) > 1e-3)
      throw InputError(
          path, row.line,
          "quaternion (qw qx qy qz) is not unit length: norm " + std::to_string(q.norm()));
    x.q_w_b = q.normalized();
    x.v_w = rows.vec3(row, 8);
    x.gyro_bias = rows.vec3(row, 11);
    x.accel_bias = rows.vec3(row, 14);
    states.push_back(x);
  }
  return states;
}

}  // namespace hs
