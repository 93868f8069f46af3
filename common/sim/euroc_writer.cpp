#include "common/sim/euroc_writer.h"

#include <cstdio>
#include <filesystem>
#include <future>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "common/core/atomic_file.h"
#include "common/core/error.h"

namespace hs::sim {
namespace fs = std::filesystem;
namespace {

void append_row(std::string& csv, int64_t t_ns, std::initializer_list<double> values) {
  csv += std::to_string(t_ns);
  char buf[32];
  for (const double v : values) {
    std::snprintf(buf, sizeof(buf), ",%.12g", v + 0.0);  // + 0.0: no "-0"
    csv += buf;
  }
  csv += '\n';
}

std::string imu_sensor_yaml(const ImuSynthOptions& imu) {
  char buf[1024];
  std::snprintf(buf, sizeof(buf),
                "%%YAML:1.0\n"
                "sensor_type: imu\n"
                "comment: hs-sim synthetic IMU (body frame)\n"
                "T_BS:\n"
                "  cols: 4\n"
                "  rows: 4\n"
                "  data: [1.0, 0.0, 0.0, 0.0,\n"
                "         0.0, 1.0, 0.0, 0.0,\n"
                "         0.0, 0.0, 1.0, 0.0,\n"
                "         0.0, 0.0, 0.0, 1.0]\n"
                "rate_hz: %.10g\n"
                "gyroscope_noise_density: %.10g     # [ rad / s / sqrt(Hz) ]\n"
                "gyroscope_random_walk: %.10g       # [ rad / s^2 / sqrt(Hz) ]\n"
                "accelerometer_noise_density: %.10g # [ m / s^2 / sqrt(Hz) ]\n"
                "accelerometer_random_walk: %.10g   # [ m / s^3 / sqrt(Hz) ]\n",
                imu.rate_hz, imu.gyro_noise_density, imu.gyro_random_walk, imu.accel_noise_density,
                imu.accel_random_walk);
  return buf;
}

nlohmann::json windows_json(const std::vector<TimeWindow>& windows) {
  nlohmann::json out = nlohmann::json::array();
  for (const TimeWindow& w : windows) out.push_back({ns_to_s(w.start_ns), ns_to_s(w.end_ns)});
  return out;
}

std::string sim_info_json(const Scenario& sc) {
  nlohmann::json gains = nlohmann::json::array();
  for (const GainStep& g : sc.events.gain_steps) gains.push_back({ns_to_s(g.t_ns), g.gain});
  const nlohmann::json info = {
      {"scenario", sc.name},
      {"seed", sc.seed},
      {"duration_s", sc.duration_s},
      {"start_time_ns", sc.start_time_ns},
      {"events",
       {{"times", "seconds from start_time_ns"},
        {"gain_steps", gains},
        {"blackouts", windows_json(sc.events.blackouts)},
        {"blackout_frames", sc.events.blackout_mode == BlackoutMode::kBlack ? "black" : "missing"},
        {"imu_gaps", windows_json(sc.events.imu_gaps)},
        {"textureless", windows_json(sc.events.textureless)}}}};
  return info.dump(2) + "\n";
}

// Removes the temporary directory unless the dataset was moved into place.
class TempDir {
 public:
  explicit TempDir(fs::path path) : path_(std::move(path)) {}
  ~TempDir() {
    std::error_code ec;
    if (!released_) fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }
  void release() { released_ = true; }

 private:
  fs::path path_;
  bool released_ = false;
};

void create_dirs(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir.string(), "cannot create directory: " + ec.message());
}

void write_pngs(const SimStereoFrame& frame, const fs::path& mav0, const std::vector<int>& params) {
  const std::string name = std::to_string(frame.t_ns) + ".png";
  const cv::Mat* images[2] = {&frame.cam0, &frame.cam1};
  for (int c = 0; c < 2; ++c) {
    const fs::path png = mav0 / ("cam" + std::to_string(c)) / "data" / name;
    if (!cv::imwrite(png.string(), *images[c], params))
      throw InputError(png.string(), "cannot write image");
  }
}

void write_frames(DatasetGenerator& gen, const fs::path& mav0, const EurocWriteOptions& options) {
  const std::vector<int> png_params{cv::IMWRITE_PNG_COMPRESSION, options.png_compression};
  std::string csv = "#timestamp [ns],filename\n";
  // Each pair is compressed and written on a second thread while the next one renders.
  std::future<void> writing;
  for (size_t i = 0; i < gen.num_frames(); ++i) {
    SimStereoFrame frame = gen.frame(i);
    if (writing.valid()) writing.get();
    csv += std::to_string(frame.t_ns) + "," + std::to_string(frame.t_ns) + ".png\n";
    writing = std::async(std::launch::async, [&mav0, &png_params, f = std::move(frame)] {
      write_pngs(f, mav0, png_params);
    });
    if (options.progress) options.progress(i + 1, gen.num_frames());
  }
  if (writing.valid()) writing.get();
  const Scenario& sc = gen.scenario();
  const CameraCalib* calibs[2] = {&sc.camera.calib.cam0, &sc.camera.calib.cam1};
  for (int c = 0; c < 2; ++c) {
    const fs::path dir = mav0 / ("cam" + std::to_string(c));
    CameraCalib calib = *calibs[c];
    calib.rate_hz = sc.camera.rate_hz;
    write_camera_yaml((dir / "sensor.yaml").string(), calib,
                      "hs-sim synthetic cam" + std::to_string(c));
    write_file_atomically((dir / "data.csv").string(), csv);
  }
}

void write_imu_and_truth(const DatasetGenerator& gen, const fs::path& mav0) {
  std::string imu =
      "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
      "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n";
  for (const ImuSample& s : gen.imu().samples)
    append_row(imu, s.t_ns,
               {s.gyro.x(), s.gyro.y(), s.gyro.z(), s.accel.x(), s.accel.y(), s.accel.z()});
  write_file_atomically((mav0 / "imu0" / "sensor.yaml").string(),
                        imu_sensor_yaml(gen.scenario().imu));
  write_file_atomically((mav0 / "imu0" / "data.csv").string(), imu);

  std::string gt =
      "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], "
      "q_RS_z [], v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], "
      "b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], b_w_RS_S_z [rad s^-1], "
      "b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]\n";
  for (const NavState& s : gen.imu().truth) {
    Eigen::Quaterniond q = s.q_w_b;
    if (q.w() < 0) q.coeffs() *= -1.0;  // one sign convention, as EuRoC
    append_row(gt, s.t_ns,
               {s.p_w_b.x(), s.p_w_b.y(), s.p_w_b.z(), q.w(), q.x(), q.y(), q.z(), s.v_w.x(),
                s.v_w.y(), s.v_w.z(), s.gyro_bias.x(), s.gyro_bias.y(), s.gyro_bias.z(),
                s.accel_bias.x(), s.accel_bias.y(), s.accel_bias.z()});
  }
  write_file_atomically((mav0 / "state_groundtruth_estimate0" / "data.csv").string(), gt);
}

void check_target(const fs::path& out, bool overwrite) {
  if (fs::exists(out) && !overwrite)
    throw InputError(out.string(), "output directory exists (use --overwrite to replace it)");
}

}  // namespace

void write_euroc(DatasetGenerator& generator, const std::string& out_dir,
                 const EurocWriteOptions& options) {
  const fs::path out = fs::path(out_dir).lexically_normal();
  const fs::path target = out.has_filename() ? out : out.parent_path();
  check_target(target, options.overwrite);
  if (target.has_parent_path()) create_dirs(target.parent_path());

  TempDir tmp(temp_path_for(target.string()));
  const fs::path mav0 = tmp.path() / "mav0";
  for (const char* sub : {"cam0/data", "cam1/data", "imu0", "state_groundtruth_estimate0"})
    create_dirs(mav0 / sub);
  write_file_atomically((mav0 / "body.yaml").string(),
                        "%YAML:1.0\ncomment: hs-sim synthetic body (= IMU frame)\n");
  write_imu_and_truth(generator, mav0);
  write_frames(generator, mav0, options);
  write_file_atomically((tmp.path() / "sim_info.json").string(),
                        sim_info_json(generator.scenario()));

  check_target(target, options.overwrite);
  std::error_code ec;
  if (fs::exists(target)) {
    const fs::path old = temp_path_for(target.string()) + ".old";
    fs::rename(target, old, ec);
    if (ec) throw InputError(target.string(), "cannot move the old output aside: " + ec.message());
    fs::rename(tmp.path(), target, ec);
    if (ec) {
      std::error_code restore;
      fs::rename(old, target, restore);
      throw InputError(target.string(), "cannot move the output into place: " + ec.message());
    }
    fs::remove_all(old, ec);
  } else {
    fs::rename(tmp.path(), target, ec);
    if (ec) throw InputError(target.string(), "cannot move the output into place: " + ec.message());
  }
  tmp.release();
}

}  // namespace hs::sim
