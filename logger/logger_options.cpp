#include "logger/logger_options.h"

#include "common/config/process_section.h"

namespace hs {

namespace {

void read_megabytes(ConfigSection& s, const std::string& key, int64_t& bytes) {
  double mb = static_cast<double>(bytes) / (1 << 20);
  if (!s.read(key, mb)) return;
  if (!(mb >= 0)) s.fail(key, "must be >= 0");
  bytes = static_cast<int64_t>(mb * (1 << 20));
}

}  // namespace

LoggerOptions load_logger_options(const std::string& path) {
  LoggerOptions o;
  LogWriterOptions& w = o.writer;
  ConfigSection top = ConfigSection::load(path);
  top.section("logger", [&](ConfigSection& s) {
    s.read("directory", w.directory);
    s.read("prefix", w.prefix);
    if (w.prefix.empty() || w.prefix.find('/') != std::string::npos)
      s.fail("prefix", "must be a non-empty file name part");
    s.read("include", o.include);
    s.read("exclude", o.exclude);
    s.read("png_images", o.png_images);
  });
  top.section("rotation", [&](ConfigSection& s) {
    read_megabytes(s, "max_file_mb", w.max_file_bytes);
    s.read_seconds("max_file_s", w.max_file_duration_ns);
    if (w.max_file_bytes < (1 << 20) || w.max_file_duration_ns <= 0)
      s.fail("max_file_mb", "files must be allowed at least 1 MB and a positive duration");
  });
  top.section("durability", [&](ConfigSection& s) {
    s.read_period("flush_period_s", w.flush_period_ns);
    read_megabytes(s, "max_buffer_mb", w.max_buffer_bytes);
    s.read("fsync", w.fsync);
  });
  top.section("disk_guard", [&](ConfigSection& s) {
    read_megabytes(s, "min_free_mb", w.min_free_bytes);
    std::string policy = w.on_disk_full == DiskFullPolicy::kStop ? "stop" : "delete_oldest";
    s.read("on_full", policy);
    if (policy != "stop" && policy != "delete_oldest")
      s.fail("on_full", "must be 'stop' or 'delete_oldest'");
    w.on_disk_full = policy == "stop" ? DiskFullPolicy::kStop : DiskFullPolicy::kDeleteOldest;
  });
  read_process_tail(top, o.heartbeat_period_ns, o.channels);
  return o;
}

}  // namespace hs
