#pragma once
// Writes a EuRoC dataset as an LCM log file whose event timestamps are the sensor times (us),
// so stock lcm-logplayer replays it with sensor-time spacing.
#include <cstdint>
#include <functional>
#include <string>

#include "common/config/channels.h"
#include "common/dataset/euroc_reader.h"
#include "common/lcm/convert.h"

namespace hs {

struct DatasetLogOptions {
  ImageEncoding encoding = ImageEncoding::kMono8;
  // Most IMU samples per imu_batch_t. A batch is also sent as soon as a frame arrives, so every
  // sample up to a frame's time reaches the subscriber before that frame. 10 = 50 ms at 200 Hz.
  int imu_batch = 10;
  ChannelNames channels;
};

struct DatasetLogSummary {
  int64_t frames = 0;
  int64_t imu_messages = 0;
  int64_t imu_samples = 0;
  int64_t ground_truth = 0;
  int64_t bytes = 0;  // message payload bytes
  int64_t first_t_ns = 0;
  int64_t last_t_ns = 0;
};

// Streams `reader` into `path` (temp file renamed into place only on success). Ground truth is
// written when the reader has it (see EurocOptions::use_ground_truth). `progress(done, total)`
// is called now and then. Throws InputError on bad images or write failures.
DatasetLogSummary write_dataset_log(const EurocReader& reader, const DatasetLogOptions& options,
                                    const std::string& path,
                                    const std::function<void(size_t, size_t)>& progress = {});

}  // namespace hs
