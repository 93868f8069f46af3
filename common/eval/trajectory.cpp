#include "common/eval/trajectory.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "common/core/atomic_file.h"
#include "common/core/csv.h"
#include "common/core/error.h"
#include "common/core/types.h"

namespace hs {
namespace {

// Year ~2096; keeps stamp arithmetic (offsets, differences) far from int64 overflow.
constexpr int64_t kMaxAbsStampNs = 4'000'000'000'000'000'000;

// Parses a plain decimal "123.456789" exactly into ns (rounding past 9 decimals), so TUM files
// written by save_tum read back bit-exact. Returns false for other spellings (e.g. exponents).
bool parse_decimal_seconds(const std::string& s, int64_t& t_ns) {
  const size_t dot = s.find('.');
  const std::string whole = s.substr(0, dot);
  const std::string frac = dot == std::string::npos ? "" : s.substr(dot + 1);
  auto all_digits = [](const std::string& d) {
    return d.find_first_not_of("0123456789") == std::string::npos;
  };
  if (whole.empty() || whole.size() > 10 || !all_digits(whole) || !all_digits(frac)) return false;
  int64_t ns = 0;
  for (size_t i = 0; i < 9; ++i) ns = ns * 10 + (i < frac.size() ? frac[i] - '0' : 0);
  if (frac.size() > 9 && frac[9] >= '5') ++ns;
  const long long sec = std::stoll(whole);
  if (sec > kMaxAbsStampNs / 1'000'000'000LL) return false;  // left to the range check
  t_ns = sec * 1'000'000'000LL + ns;
  return true;
}

int64_t tum_stamp_ns(const CsvReader& reader, const CsvRow& row) {
  int64_t t_ns = 0;
  if (parse_decimal_seconds(row.fields[0], t_ns)) return t_ns;
  const double t_s = reader.double_at(row, 0);
  if (std::abs(t_s) > 9e9)
    throw InputError(reader.path(), row.line, "timestamp out of range: " + row.fields[0]);
  return s_to_ns(t_s);
}

// Columns of position and quaternion for each format.
struct Layout {
  size_t p, qw, qx, qy, qz;
};

StampedPose parse_pose(const CsvReader& reader, const CsvRow& row, TrajectoryFormat format) {
  StampedPose pose;
  Layout col{};
  if (format == TrajectoryFormat::kTum) {
    if (row.fields.size() != 8)
      throw InputError(reader.path(), row.line,
                       "TUM line needs 8 fields (t x y z qx qy qz qw), found " +
                           std::to_string(row.fields.size()));
    pose.t_ns = tum_stamp_ns(reader, row);
    col = {1, 7, 4, 5, 6};
  } else {
    reader.require_fields(row, 8);
    pose.t_ns = reader.int64_at(row, 0);
    col = {1, 4, 5, 6, 7};
  }
  if (std::llabs(pose.t_ns) > kMaxAbsStampNs)
    throw InputError(reader.path(), row.line, "timestamp out of range: " + row.fields[0]);
  const Eigen::Vector3d p(reader.double_at(row, col.p), reader.double_at(row, col.p + 1),
                          reader.double_at(row, col.p + 2));
  Eigen::Quaterniond q(reader.double_at(row, col.qw), reader.double_at(row, col.qx),
                       reader.double_at(row, col.qy), reader.double_at(row, col.qz));
  if (std::abs(q.norm() - 1.0) > kQuatNormTolerance)
    throw InputError(reader.path(), row.line,
                     "quaternion is not unit (norm " + std::to_string(q.norm()) + ")");
  q.normalize();
  pose.T_w_b.linear() = q.toRotationMatrix();
  pose.T_w_b.translation() = p;
  return pose;
}

}  // namespace

TrajectoryFormat detect_trajectory_format(const std::string& path) {
  CsvReader reader(path, "\n");  // one field per line: only the raw first data line is needed
  CsvRow row;
  if (!reader.next(row)) throw InputError(path, "no poses in file");
  return row.fields[0].find(',') != std::string::npos ? TrajectoryFormat::kEuroc
                                                      : TrajectoryFormat::kTum;
}

Trajectory load_trajectory(const std::string& path, TrajectoryFormat format) {
  if (format == TrajectoryFormat::kAuto) format = detect_trajectory_format(path);
  CsvReader reader(path, format == TrajectoryFormat::kTum ? " \t" : ",");
  Trajectory trajectory;
  CsvRow row;
  while (reader.next(row)) {
    const StampedPose pose = parse_pose(reader, row, format);
    if (!trajectory.poses.empty() && pose.t_ns <= trajectory.poses.back().t_ns)
      throw InputError(path, row.line,
                       pose.t_ns == trajectory.poses.back().t_ns
                           ? "duplicate timestamp"
                           : "timestamp decreases (must be strictly increasing)");
    trajectory.poses.push_back(pose);
  }
  if (trajectory.poses.empty()) throw InputError(path, "no poses in file");
  return trajectory;
}

void save_tum(const std::string& path, const Trajectory& trajectory) {
  std::ostringstream out;
  out << "# timestamp[s] tx ty tz qx qy qz qw\n";
  char line[256];
  for (const StampedPose& pose : trajectory.poses) {
    const Eigen::Vector3d p = pose.T_w_b.translation();
    const Eigen::Quaterniond q(pose.T_w_b.linear());
    const int64_t sec = pose.t_ns / 1000000000LL;
    const int64_t frac = pose.t_ns % 1000000000LL;
    if (frac < 0) throw InputError(path, "cannot write negative timestamps as TUM");
    std::snprintf(line, sizeof(line), "%lld.%09lld %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n",
                  static_cast<long long>(sec), static_cast<long long>(frac), p.x(), p.y(), p.z(),
                  q.x(), q.y(), q.z(), q.w());
    out << line;
  }
  write_file_atomically(path, out.str());
}

TrajectoryFormat parse_trajectory_format(const std::string& name) {
  if (name == "auto") return TrajectoryFormat::kAuto;
  if (name == "tum") return TrajectoryFormat::kTum;
  if (name == "euroc") return TrajectoryFormat::kEuroc;
  throw InputError("unknown trajectory format '" + name + "' (auto, tum, euroc)");
}

const char* format_name(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kTum:
      return "tum";
    case TrajectoryFormat::kEuroc:
      return "euroc";
    case TrajectoryFormat::kAuto:
      break;
  }
  return "auto";
}

}  // namespace hs
