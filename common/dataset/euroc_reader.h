#pragma once
// EuRoC ASL folder reader. Parses every CSV up front (cheap) and loads images only on demand.
//
// Policy for bad input (every case is reported, never silent):
//   fatal (InputError naming file:line): no mav0/ or cam0/, missing or malformed cam0/imu0 CSV,
//     malformed row, non-increasing or duplicate timestamp in any CSV, empty cam0 or imu0,
//     image listed for a used frame but missing, image that does not decode, is not 8-bit mono
//     or differs in size from the first cam0 image (checked when the frame is loaded),
//     malformed ground-truth CSV when present.
//   dropped and reported in dropped(): cam0/cam1 rows without a partner of the exact same
//     timestamp (real EuRoC cam1 lists have such rows).
//   optional: cam1 absent -> mono; state_groundtruth_estimate0 absent -> no ground truth.
#include <opencv2/core/types.hpp>
#include <string>
#include <vector>

#include "common/core/types.h"
#include "common/dataset/stereo_frame.h"

namespace hs {

struct EurocOptions {
  bool use_cam1 = true;          // false: mono from cam0 even when cam1 exists
  bool use_ground_truth = true;  // false: ignore state_groundtruth_estimate0
};

// Image files of one used frame, with their data.csv rows for error messages.
struct FrameFiles {
  int64_t t_ns = 0;
  std::string cam0;
  long cam0_line = 0;
  std::string cam1;  // empty for mono
  long cam1_line = 0;
};

class EurocReader {
 public:
  // `path` is the dataset root (containing mav0/) or mav0/ itself. Throws InputError.
  explicit EurocReader(const std::string& path, const EurocOptions& options = {});

  const std::string& mav0() const { return mav0_; }
  bool stereo() const { return stereo_; }
  const std::vector<FrameFiles>& frames() const { return frames_; }
  const std::vector<ImuSample>& imu() const { return imu_; }
  const std::vector<NavState>& ground_truth() const { return ground_truth_; }
  bool has_ground_truth_folder() const { return has_ground_truth_folder_; }
  // Size of the first cam0 image, which every image must have.
  cv::Size image_size() const { return image_size_; }
  // One "file:line: why" entry per dropped row.
  const std::vector<std::string>& dropped() const { return dropped_; }

  // Loads frame i's images (seq = i). Throws InputError for unreadable or inconsistent images.
  StereoFrame load_frame(size_t i) const;

 private:
  cv::Mat load_image(const std::string& csv, long line, const std::string& path) const;
  void pair_frames(const std::string& cam0_dir, const std::string& cam1_dir);

  std::string mav0_;
  bool stereo_ = false;
  bool has_ground_truth_folder_ = false;
  std::vector<FrameFiles> frames_;
  std::vector<ImuSample> imu_;
  std::vector<NavState> ground_truth_;
  cv::Size image_size_;
  std::vector<std::string> dropped_;
};

}  // namespace hs
