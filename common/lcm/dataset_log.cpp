#include "common/lcm/dataset_log.h"

#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <stdexcept>
#include <vector>

#include "common/core/atomic_file.h"
#include "common/core/error.h"
#include "common/dataset/euroc_stream.h"

namespace hs {
namespace {

class LogWriter {
 public:
  LogWriter(const std::string& path, DatasetLogSummary& summary)
      : path_(path),
        temp_(temp_path_for(path)),
        log_(std::make_unique<lcm::LogFile>(temp_, "w")),
        summary_(summary) {
    if (!log_->good()) throw InputError(path_, "cannot create log file " + temp_);
  }
  ~LogWriter() {
    if (log_) {
      log_.reset();
      std::remove(temp_.c_str());
    }
  }

  template <class Msg>
  void write(const std::string& channel, int64_t t_ns, const Msg& msg) {
    buffer_.resize(static_cast<size_t>(msg.getEncodedSize()));
    if (msg.encode(buffer_.data(), 0, static_cast<int>(buffer_.size())) < 0)
      throw std::runtime_error("LCM encoding failed on channel " + channel);
    lcm::LogEvent event;
    event.eventnum = events_++;
    event.timestamp = t_ns / 1000;  // sensor time in microseconds
    event.channel = channel;
    event.datalen = static_cast<int32_t>(buffer_.size());
    event.data = buffer_.data();
    if (log_->writeEvent(&event) != 0) throw InputError(path_, "write failed (disk full?)");
    summary_.bytes += event.datalen;
    if (events_ == 1) summary_.first_t_ns = t_ns;
    summary_.last_t_ns = t_ns;
  }

  void commit() {
    const bool ok = std::fflush(log_->getFilePtr()) == 0 && !std::ferror(log_->getFilePtr());
    log_.reset();  // closes the file
    if (!ok) {
      std::remove(temp_.c_str());
      throw InputError(path_, "write failed (disk full?)");
    }
    commit_temp_file(temp_, path_);
  }

 private:
  std::string path_;
  std::string temp_;
  std::unique_ptr<lcm::LogFile> log_;
  DatasetLogSummary& summary_;
  std::vector<uint8_t> buffer_;
  int64_t events_ = 0;
};

}  // namespace

DatasetLogSummary write_dataset_log(const EurocReader& reader, const DatasetLogOptions& options,
                                    const std::string& path,
                                    const std::function<void(size_t, size_t)>& progress) {
  if (options.imu_batch < 1) throw InputError("IMU batch size must be at least 1");
  DatasetLogSummary summary;
  LogWriter log(path, summary);
  const ChannelNames& ch = options.channels;
  std::vector<ImuSample> batch;
  const auto flush_imu = [&] {
    if (batch.empty()) return;
    log.write(ch.imu, batch.back().t_ns, imu_batch_to_msg(batch, summary.imu_messages));
    ++summary.imu_messages;
    summary.imu_samples += static_cast<int64_t>(batch.size());
    batch.clear();
  };

  EurocStream stream(reader);
  DatasetEvent event;
  while (stream.next(event)) {
    if (const auto* imu = std::get_if<ImuSample>(&event)) {
      batch.push_back(*imu);
      if (static_cast<int>(batch.size()) >= options.imu_batch) flush_imu();
    } else if (const auto* gt = std::get_if<NavState>(&event)) {
      log.write(ch.ground_truth, gt->t_ns, ground_truth_to_msg(*gt));
      ++summary.ground_truth;
    } else {
      const auto& frame = std::get<StereoFrame>(event);
      flush_imu();
      log.write(ch.cam_stereo, frame.t_ns, frame_to_msg(frame, options.encoding));
      ++summary.frames;
      if (progress) progress(stream.position(), stream.size());
    }
  }
  flush_imu();
  log.commit();
  if (progress) progress(stream.size(), stream.size());
  return summary;
}

}  // namespace hs
