#include "common/calib/camera_calib.h"

#include <yaml-cpp/yaml.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "common/core/atomic_file.h"
#include "common/core/error.h"

namespace hs {
namespace {

CameraCalib make_calib(const double (&T)[12], double fx, double fy, double cx, double cy, double k1,
                       double k2, double p1, double p2) {
  CameraCalib c;
  c.intrinsics = {fx, fy, cx, cy, k1, k2, p1, p2, 752, 480};
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int i = 0; i < 12; ++i) m(i / 4, i % 4) = T[i];
  const Eigen::Matrix3d R = Eigen::Quaterniond(m.topLeftCorner<3, 3>()).normalized().matrix();
  c.T_b_c.linear() = R;
  c.T_b_c.translation() = m.topRightCorner<3, 1>();
  c.rate_hz = 20.0;
  return c;
}

// yaml-cpp marks are 0-based.
long line_of(const YAML::Node& node) {
  return node.Mark().line + 1;
}

YAML::Node require(const std::string& path, const YAML::Node& parent, const char* key) {
  const YAML::Node node = parent[key];
  if (!node) throw InputError(path, line_of(parent), std::string("missing key '") + key + "'");
  return node;
}

std::vector<double> read_numbers(const std::string& path, const YAML::Node& parent, const char* key,
                                 size_t count) {
  const YAML::Node node = require(path, parent, key);
  if (!node.IsSequence() || node.size() != count) {
    throw InputError(
        path, line_of(node),
        std::string("'") + key + "' must be a list of " + std::to_string(count) + " numbers");
  }
  std::vector<double> out;
  for (const YAML::Node& v : node) {
    double x = 0;
    if (!YAML::convert<double>::decode(v, x) || !std::isfinite(x)) {
      throw InputError(path, line_of(v), std::string("'") + key + "' has a non-numeric value");
    }
    out.push_back(x);
  }
  return out;
}

std::string read_string(const std::string& path, const YAML::Node& parent, const char* key) {
  const YAML::Node node = require(path, parent, key);
  if (!node.IsScalar())
    throw InputError(path, line_of(node), std::string("'") + key + "' must be text");
  return node.Scalar();
}

// EuRoC files start with "%YAML:1.0", which yaml-cpp rejects; blank it to keep line numbers.
std::string load_text(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open camera calibration");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  if (text.rfind("%YAML", 0) == 0) text[0] = '#';
  return text;
}

// Shortest text that reads back as exactly the same double.
std::string number(double x) {
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, x).ptr);
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (const char ch : s) {
    if (ch == '"' || ch == '\\') out += '\\';
    out += (ch == '\n' || ch == '\r') ? ' ' : ch;
  }
  return out + "\"";
}

}  // namespace

StereoCalib euroc_stereo_calib() {
  const double T0[12] = {0.0148655429818,  -0.999880929698,  0.00414029679422, -0.0216401454975,
                         0.999557249008,   0.0149672133247,  0.025715529948,   -0.064676986768,
                         -0.0257744366974, 0.00375618835797, 0.999660727178,   0.00981073058949};
  const double T1[12] = {0.0125552670891,  -0.999755099723, 0.0182237714554, -0.0198435579556,
                         0.999598781151,   0.0130119051815, 0.0251588363115, 0.0453689425024,
                         -0.0253898008918, 0.0179005838253, 0.999517347078,  0.00786212447038};
  StereoCalib s;
  s.cam0 = make_calib(T0, 458.654, 457.296, 367.215, 248.375, -0.28340811, 0.07395907, 0.00019359,
                      1.76187114e-05);
  s.cam1 = make_calib(T1, 457.587, 456.134, 379.999, 255.238, -0.28368365, 0.07451284, -0.00010473,
                      -3.55590700e-05);
  return s;
}

CameraCalib read_camera_yaml(const std::string& path) {
  const std::string text = load_text(path);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(path, e.mark.line + 1, "invalid YAML: " + e.msg);
  }
  if (!root.IsMap()) throw InputError(path, "not a YAML map");
  try {
    const std::string model = read_string(path, root, "camera_model");
    if (model != "pinhole") {
      throw InputError(path, line_of(root["camera_model"]),
                       "unsupported camera_model '" + model + "' (only pinhole)");
    }
    const std::string dist = read_string(path, root, "distortion_model");
    if (dist != "radial-tangential" && dist != "radtan") {
      throw InputError(path, line_of(root["distortion_model"]),
                       "unsupported distortion_model '" + dist + "' (only radial-tangential)");
    }
    const YAML::Node T_BS = require(path, root, "T_BS");
    const std::vector<double> T = read_numbers(path, T_BS, "data", 16);
    Eigen::Matrix4d m;
    for (int i = 0; i < 16; ++i) m(i / 4, i % 4) = T[i];
    const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
    if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-5 || R.determinant() < 0 ||
        m.row(3) != Eigen::RowVector4d(0, 0, 0, 1)) {
      throw InputError(path, line_of(T_BS["data"]), "T_BS is not a rigid transform");
    }
    const std::vector<double> res = read_numbers(path, root, "resolution", 2);
    const std::vector<double> k = read_numbers(path, root, "intrinsics", 4);
    const std::vector<double> d = read_numbers(path, root, "distortion_coefficients", 4);
    CameraCalib c;
    c.intrinsics = {k[0],
                    k[1],
                    k[2],
                    k[3],
                    d[0],
                    d[1],
                    d[2],
                    d[3],
                    static_cast<int>(res[0]),
                    static_cast<int>(res[1])};
    if (res[0] < 1 || res[1] < 1 || res[0] != std::floor(res[0]) || res[1] != std::floor(res[1])) {
      throw InputError(path, line_of(root["resolution"]), "resolution must be positive integers");
    }
    if (!(k[0] > 0 && k[1] > 0))
      throw InputError(path, line_of(root["intrinsics"]), "fx, fy must be > 0");
    c.T_b_c.linear() = Eigen::Quaterniond(R).normalized().matrix();
    c.T_b_c.translation() = m.topRightCorner<3, 1>();
    const YAML::Node rate_node = require(path, root, "rate_hz");
    if (!YAML::convert<double>::decode(rate_node, c.rate_hz) || !(c.rate_hz > 0)) {
      throw InputError(path, line_of(rate_node), "rate_hz must be a positive number");
    }
    return c;
  } catch (const YAML::Exception& e) {
    throw InputError(path, e.mark.line + 1, "bad camera calibration: " + e.msg);
  }
}

void write_camera_yaml(const std::string& path, const CameraCalib& calib,
                       const std::string& comment) {
  const PinholeRadtan& k = calib.intrinsics;
  const Eigen::Matrix4d T = calib.T_b_c.matrix();
  std::ostringstream out;
  out << "%YAML:1.0\n# General sensor definitions.\nsensor_type: camera\ncomment: "
      << quoted(comment) << "\n\n# Sensor extrinsics wrt. the body-frame.\nT_BS:\n  cols: 4\n"
      << "  rows: 4\n  data: [";
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      out << number(T(r, c)) << (r == 3 && c == 3 ? "]\n" : (c == 3 ? ",\n         " : ", "));
    }
  }
  out << "\n# Camera specific definitions.\nrate_hz: " << number(calib.rate_hz) << "\nresolution: ["
      << k.width << ", " << k.height << "]\ncamera_model: pinhole\n"
      << "intrinsics: [" << number(k.fx) << ", " << number(k.fy) << ", " << number(k.cx) << ", "
      << number(k.cy) << "] #fu, fv, cu, cv\n"
      << "distortion_model: radial-tangential\ndistortion_coefficients: [" << number(k.k1) << ", "
      << number(k.k2) << ", " << number(k.p1) << ", " << number(k.p2) << "]\n";
  write_file_atomically(path, out.str());
}

StereoCalib read_stereo_calib(const std::string& mav0_dir) {
  const CameraCalib cam0 = read_camera_yaml(mav0_dir + "/cam0/sensor.yaml");
  const std::string cam1 = mav0_dir + "/cam1/sensor.yaml";
  return {cam0, std::filesystem::exists(mav0_dir + "/cam1") ? read_camera_yaml(cam1) : cam0};
}

}  // namespace hs
