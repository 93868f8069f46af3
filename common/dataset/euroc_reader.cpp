#include "common/dataset/euroc_reader.h"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "common/core/error.h"
#include "common/dataset/euroc_csv.h"

namespace hs {
namespace fs = std::filesystem;
namespace {

bool is_dir(const std::string& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

std::string find_mav0(const std::string& path) {
  if (is_dir(path + "/mav0")) return path + "/mav0";
  if (is_dir(path + "/cam0")) return path;
  if (!is_dir(path)) throw InputError(path, "dataset folder does not exist");
  throw InputError(path, "not a EuRoC ASL folder: neither mav0/ nor cam0/ inside");
}

std::string row_ref(const std::string& csv, long line) {
  return csv + ":" + std::to_string(line);
}

}  // namespace

EurocReader::EurocReader(const std::string& path, const EurocOptions& options)
    : mav0_(find_mav0(path)) {
  const std::string cam0_dir = mav0_ + "/cam0";
  const std::string cam1_dir = mav0_ + "/cam1";
  if (!is_dir(cam0_dir)) throw InputError(mav0_, "cam0/ folder missing");
  if (!is_dir(mav0_ + "/imu0")) throw InputError(mav0_, "imu0/ folder missing (IMU is required)");
  stereo_ = options.use_cam1 && is_dir(cam1_dir);
  pair_frames(cam0_dir, cam1_dir);

  imu_ = read_imu_csv(mav0_ + "/imu0/data.csv");
  if (imu_.empty()) throw InputError(mav0_ + "/imu0/data.csv", "no IMU samples");

  const std::string gt_dir = mav0_ + "/state_groundtruth_estimate0";
  has_ground_truth_folder_ = is_dir(gt_dir);
  if (options.use_ground_truth && has_ground_truth_folder_)
    ground_truth_ = read_ground_truth_csv(gt_dir + "/data.csv");

  const FrameFiles& first = frames_.front();
  image_size_ = load_image(cam0_dir + "/data.csv", first.cam0_line, first.cam0).size();
}

void EurocReader::pair_frames(const std::string& cam0_dir, const std::string& cam1_dir) {
  const std::string csv0 = cam0_dir + "/data.csv";
  const std::string csv1 = cam1_dir + "/data.csv";
  const std::vector<ImageEntry> cam0 = read_camera_csv(cam0_dir);
  if (!stereo_) {
    for (const ImageEntry& e : cam0) frames_.push_back({e.t_ns, e.path, e.line, "", 0});
  } else {
    const std::vector<ImageEntry> cam1 = read_camera_csv(cam1_dir);
    // Both lists strictly increase, so exact-timestamp pairing is a single merge pass.
    size_t i = 0, j = 0;
    while (i < cam0.size() || j < cam1.size()) {
      if (j == cam1.size() || (i < cam0.size() && cam0[i].t_ns < cam1[j].t_ns)) {
        dropped_.push_back(row_ref(csv0, cam0[i].line) + ": frame " + std::to_string(cam0[i].t_ns) +
                           " has no cam1 image with the same timestamp");
        ++i;
      } else if (i == cam0.size() || cam1[j].t_ns < cam0[i].t_ns) {
        dropped_.push_back(row_ref(csv1, cam1[j].line) + ": frame " + std::to_string(cam1[j].t_ns) +
                           " has no cam0 image with the same timestamp");
        ++j;
      } else {
        frames_.push_back({cam0[i].t_ns, cam0[i].path, cam0[i].line, cam1[j].path, cam1[j].line});
        ++i, ++j;
      }
    }
  }
  if (frames_.empty())
    throw InputError(csv0, stereo_ ? "no cam0/cam1 pairs with equal timestamps" : "no frames");
  for (const FrameFiles& f : frames_) {
    if (!fs::is_regular_file(f.cam0))
      throw InputError(csv0, f.cam0_line, "image file listed but missing: " + f.cam0);
    if (stereo_ && !fs::is_regular_file(f.cam1))
      throw InputError(csv1, f.cam1_line, "image file listed but missing: " + f.cam1);
  }
}

cv::Mat EurocReader::load_image(const std::string& csv, long line, const std::string& path) const {
  const cv::Mat image = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (image.empty()) throw InputError(csv, line, "cannot read or decode image " + path);
  if (image.type() != CV_8UC1)
    throw InputError(csv, line,
                     "image " + path + " is not 8-bit mono (" + std::to_string(image.channels()) +
                         " channels, depth code " + std::to_string(image.depth()) + ")");
  if (!image_size_.empty() && image.size() != image_size_)
    throw InputError(csv, line,
                     "image " + path + " is " + std::to_string(image.cols) + "x" +
                         std::to_string(image.rows) + ", but the first cam0 image is " +
                         std::to_string(image_size_.width) + "x" +
                         std::to_string(image_size_.height));
  return image;
}

StereoFrame EurocReader::load_frame(size_t i) const {
  const FrameFiles& f = frames_.at(i);
  StereoFrame frame;
  frame.t_ns = f.t_ns;
  frame.seq = static_cast<int64_t>(i);
  frame.cam0 = load_image(mav0_ + "/cam0/data.csv", f.cam0_line, f.cam0);
  if (stereo_) frame.cam1 = load_image(mav0_ + "/cam1/data.csv", f.cam1_line, f.cam1);
  return frame;
}

}  // namespace hs
