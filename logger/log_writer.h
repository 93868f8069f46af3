#pragma once
// The logger's files: LCM log files (lcm_log_format.h) in one directory, rotated by size and by
// age, named PREFIX-YYYYmmdd-HHMMSS-NNNN.lcmlog (UTC at opening, then a counter) so that names
// sort by time, each with a FILE.manifest.json written when it is closed.
//
// Crash safety: events are buffered and written + fdatasync'ed at least every flush_period, so
// a SIGKILL or power cut loses at most that much (and leaves at most one torn event, which
// scan_log_file skips). Disk space: before every flush and file the free space is checked; below
// min_free_bytes the writer deletes its own oldest files (kDeleteOldest) or stops recording
// (kStop) and resumes when space is back. A write error (ENOSPC included) stops recording with
// the reason; nothing here throws on disk errors: status() says what happened.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "logger/log_manifest.h"

namespace hs {

enum class DiskFullPolicy { kStop, kDeleteOldest };

struct LogWriterOptions {
  std::string directory = "logs";
  std::string prefix = "hs";
  int64_t max_file_bytes = 512ll << 20;
  int64_t max_file_duration_ns = 600'000'000'000;
  int64_t flush_period_ns = 50'000'000;
  int64_t max_buffer_bytes = 8ll << 20;  // flushed sooner when this much is waiting
  int64_t min_free_bytes = 256ll << 20;
  DiskFullPolicy on_disk_full = DiskFullPolicy::kStop;
  bool fsync = true;  // fdatasync at every flush (power-loss safety)
};

struct LogWriterStatus {
  bool recording = true;  // false: stopped by the disk guard or a write error
  std::string message;    // why not recording, or the last deletion; empty when all is well
  std::string current_file;
  int64_t events_written = 0;
  int64_t events_dropped = 0;  // while not recording
  int64_t bytes_written = 0;
  int64_t files_closed = 0;
  int64_t files_deleted = 0;
  int64_t write_errors = 0;
  int64_t free_bytes = -1;  // at the last check
  int64_t buffered_bytes = 0;
};

class LogWriter {
 public:
  // `free_bytes(dir)`: free space for an unprivileged writer (default: statvfs).
  explicit LogWriter(const LogWriterOptions& options,
                     std::function<int64_t(const std::string&)> free_bytes = {});
  ~LogWriter();
  LogWriter(const LogWriter&) = delete;
  LogWriter& operator=(const LogWriter&) = delete;

  // Queues one received message (utime: receive time, us; now_ns: monotonic clock).
  void write(const std::string& channel, int64_t utime, const uint8_t* data, size_t size,
             int64_t now_ns);
  // Flushes and rotates when due; while stopped, checks whether recording can resume.
  void poll(int64_t now_ns);
  // Flushes, closes the file and writes its manifest.
  void close();

  const LogWriterStatus& status() const { return status_; }
  // The closed files of this writer's prefix in the directory, oldest first.
  std::vector<std::string> own_files() const;

 private:
  struct Pending {  // a buffered event, for the manifest once it is on disk
    std::string channel;
    int64_t utime, bytes, seq;
  };

  bool open_file(int64_t now_ns);
  bool flush();
  // The first `bytes_on_disk` bytes of the buffer reached the file: their whole events go to
  // the manifest and the counts, and leave pending_.
  void commit_pending(size_t bytes_on_disk);
  void close_file();   // flush, then finish
  void finish_file();  // close the descriptor and write the manifest
  // Empty when there is room for `needed` more bytes (after deleting own old files, with
  // kDeleteOldest), else why not.
  std::string make_space(int64_t needed);
  // Stops recording: buffered events are dropped, the file is finished.
  void stop(const std::string& why);

  LogWriterOptions options_;
  std::function<int64_t(const std::string&)> free_bytes_;
  LogWriterStatus status_;
  int fd_ = -1;
  std::string path_;
  int64_t file_bytes_ = 0;
  int64_t opened_ns_ = 0;
  int64_t last_flush_ns_ = 0;
  int64_t last_resume_check_ns_ = 0;
  int64_t next_event_number_ = 0;
  int file_counter_ = 0;
  std::vector<uint8_t> buffer_;
  std::vector<Pending> pending_;
  LogManifest manifest_;
};

// statvfs free space available to unprivileged users, or -1.
int64_t filesystem_free_bytes(const std::string& directory);

}  // namespace hs
