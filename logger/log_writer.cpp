#include "logger/log_writer.h"

#include <fcntl.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "common/core/atomic_file.h"
#include "common/core/error.h"
#include "common/core/wall_clock.h"
#include "logger/lcm_log_format.h"

namespace hs {

namespace fs = std::filesystem;

namespace {

constexpr int64_t kResumeCheckPeriodNs = 1'000'000'000;
constexpr const char* kSuffix = ".lcmlog";

std::string mib(int64_t bytes) {
  return std::to_string(bytes >> 20) + " MiB";
}

}  // namespace

int64_t filesystem_free_bytes(const std::string& directory) {
  struct statvfs s {};
  if (::statvfs(directory.c_str(), &s) != 0) return -1;
  return static_cast<int64_t>(s.f_bavail) * static_cast<int64_t>(s.f_frsize);
}

LogWriter::LogWriter(const LogWriterOptions& options,
                     std::function<int64_t(const std::string&)> free_bytes)
    : options_(options), free_bytes_(free_bytes ? std::move(free_bytes) : filesystem_free_bytes) {
  std::error_code ec;
  fs::create_directories(options_.directory, ec);
  if (!fs::is_directory(options_.directory))
    throw InputError(options_.directory + ": cannot create the log directory" +
                     (ec ? " (" + ec.message() + ")" : ""));
}

LogWriter::~LogWriter() {
  close();
}

std::vector<std::string> LogWriter::own_files() const {
  std::vector<std::string> files;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(options_.directory, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(options_.prefix + "-", 0) == 0 && e.path().extension() == kSuffix &&
        e.path().string() != path_)
      files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

void LogWriter::stop(const std::string& why) {
  status_.events_dropped += static_cast<int64_t>(pending_.size());
  buffer_.clear();
  pending_.clear();
  status_.buffered_bytes = 0;
  finish_file();
  status_.recording = false;
  status_.message = why;
}

std::string LogWriter::make_space(int64_t needed) {
  status_.free_bytes = free_bytes_(options_.directory);
  if (status_.free_bytes < 0) return "";  // unknown: write() reports real errors
  const auto short_of_space = [&] { return status_.free_bytes - needed < options_.min_free_bytes; };
  if (!short_of_space()) return "";
  if (options_.on_disk_full == DiskFullPolicy::kDeleteOldest) {
    for (const std::string& old : own_files()) {
      std::error_code ec;
      fs::remove(old, ec);
      fs::remove(old + ".manifest.json", ec);
      ++status_.files_deleted;
      status_.message = "disk guard: deleted " + fs::path(old).filename().string();
      status_.free_bytes = free_bytes_(options_.directory);
      if (!short_of_space()) return "";
    }
  }
  return "disk guard: " + mib(status_.free_bytes) + " free, below the " +
         mib(options_.min_free_bytes) + " minimum" +
         (options_.on_disk_full == DiskFullPolicy::kDeleteOldest
              ? " with no file of its own left to delete"
              : "") +
         ": recording stopped";
}

bool LogWriter::open_file(int64_t now_ns) {
  if (const std::string why = make_space(0); !why.empty()) {
    stop(why);
    return false;
  }
  for (;;) {
    char counter[16];
    std::snprintf(counter, sizeof counter, "%04d", file_counter_++);
    path_ = (fs::path(options_.directory) /
             (options_.prefix + "-" + wall_clock_text("%Y%m%d-%H%M%S", TimeZone::kUtc) + "-" +
              counter + kSuffix))
                .string();
    fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd_ >= 0) break;
    if (errno != EEXIST) {
      const std::string why = std::strerror(errno);
      path_.clear();
      ++status_.write_errors;
      stop("cannot create a log file in " + options_.directory + ": " + why);
      return false;
    }
  }
  file_bytes_ = 0;
  opened_ns_ = now_ns;
  last_flush_ns_ = now_ns;
  manifest_ = LogManifest();
  status_.current_file = path_;
  return true;
}

bool LogWriter::flush() {
  if (fd_ < 0) return false;
  if (buffer_.empty()) return true;
  if (const std::string why = make_space(static_cast<int64_t>(buffer_.size())); !why.empty()) {
    stop(why);
    return false;
  }
  size_t done = 0;
  while (done < buffer_.size()) {
    const ssize_t n = ::write(fd_, buffer_.data() + done, buffer_.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      ++status_.write_errors;
      // The events that reached the file whole count as written (readers skip the torn one).
      commit_pending(done);
      stop("write to " + path_ + " failed: " + (n < 0 ? std::strerror(errno) : "no progress") +
           ": recording stopped");
      return false;
    }
    done += static_cast<size_t>(n);
  }
  commit_pending(buffer_.size());
  buffer_.clear();
  status_.buffered_bytes = 0;
  if (options_.fsync && ::fdatasync(fd_) != 0) {
    ++status_.write_errors;
    stop("fdatasync of " + path_ + " failed: " + std::strerror(errno) + ": recording stopped");
    return false;
  }
  return true;
}

void LogWriter::commit_pending(size_t bytes_on_disk) {
  status_.bytes_written += static_cast<int64_t>(bytes_on_disk);
  file_bytes_ += static_cast<int64_t>(bytes_on_disk);
  size_t end = 0, whole = 0;
  for (; whole < pending_.size(); ++whole) {
    const Pending& p = pending_[whole];
    end += kLcmLogHeaderSize + p.channel.size() + static_cast<size_t>(p.bytes);
    if (end > bytes_on_disk) break;
    manifest_.add(p.channel, p.utime, p.bytes, p.seq);
  }
  status_.events_written += static_cast<int64_t>(whole);
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(whole));
}

void LogWriter::close_file() {
  if (fd_ >= 0 && flush()) finish_file();
}

void LogWriter::finish_file() {
  if (fd_ < 0) return;
  ::close(fd_);
  fd_ = -1;
  ++status_.files_closed;
  try {
    write_file_atomically(path_ + ".manifest.json", manifest_.to_json().dump(2) + "\n");
  } catch (const std::exception& e) {
    ++status_.write_errors;
    status_.message = std::string("manifest not written: ") + e.what();
  }
  path_.clear();
  status_.current_file.clear();
}

void LogWriter::close() {
  close_file();
}

void LogWriter::write(const std::string& channel, int64_t utime, const uint8_t* data, size_t size,
                      int64_t now_ns) {
  if (!status_.recording || (fd_ < 0 && !open_file(now_ns))) {
    ++status_.events_dropped;
    return;
  }
  append_log_event(next_event_number_++, utime, channel, data, size, &buffer_);
  pending_.push_back({channel, utime, static_cast<int64_t>(size), message_seq(data, size)});
  status_.buffered_bytes = static_cast<int64_t>(buffer_.size());
  if (static_cast<int64_t>(buffer_.size()) >= options_.max_buffer_bytes) flush();
  poll(now_ns);
}

void LogWriter::poll(int64_t now_ns) {
  if (!status_.recording) {
    if (now_ns - last_resume_check_ns_ < kResumeCheckPeriodNs) return;
    last_resume_check_ns_ = now_ns;
    const int64_t free = free_bytes_(options_.directory);
    status_.free_bytes = free;
    if (free >= 0 && free < options_.min_free_bytes) return;
    status_.recording = true;
    status_.message = "recording resumed (" + mib(free) + " free)";
    return;
  }
  if (fd_ < 0) return;
  if (now_ns - last_flush_ns_ >= options_.flush_period_ns) {
    last_flush_ns_ = now_ns;
    if (!flush()) return;
  }
  if (file_bytes_ + static_cast<int64_t>(buffer_.size()) >= options_.max_file_bytes ||
      now_ns - opened_ns_ >= options_.max_file_duration_ns) {
    close_file();  // the next event opens the next file
  }
}

}  // namespace hs
