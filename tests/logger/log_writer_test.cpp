// Rotation, crash-safe flushing and the disk guard of the logger's writer, on real files; the
// disk running full on a real (tiny tmpfs) filesystem where one can be mounted.
#include "logger/log_writer.h"

#include <gtest/gtest.h>
#include <sys/mount.h>

#include <unistd.h>
#include <cerrno>
#include <cstring>

#include <filesystem>
#include <fstream>

#include "logger/lcm_log_format.h"
#include "tests/dataset/dataset_test_util.h"

namespace hs {
namespace {

namespace fs = std::filesystem;
constexpr int64_t kMs = 1'000'000;

class LogWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    options_.directory = dir_;
    options_.min_free_bytes = 0;
    options_.fsync = false;  // the tests read back through the page cache
  }
  // Writes `n` events of `bytes` each on CHAN, 10 ms apart starting at t0.
  static void write_events(LogWriter& w, int n, size_t bytes, int64_t t0_ns, int64_t* last_ns) {
    for (int i = 0; i < n; ++i) {
      const std::vector<uint8_t> data(bytes, static_cast<uint8_t>(i));
      *last_ns = t0_ns + i * 10 * kMs;
      w.write("CHAN", *last_ns / 1000, data.data(), data.size(), *last_ns);
    }
  }
  std::vector<LogEvent> all_events(const LogWriter& w) const {
    std::vector<LogEvent> out;
    for (const std::string& f : w.own_files()) {
      const LogScan s = scan_log_file(f);
      out.insert(out.end(), s.events.begin(), s.events.end());
    }
    return out;
  }

  test::TempDir tmp_;
  std::string dir_ = tmp_.path() + "/logs";
  LogWriterOptions options_;
};

TEST_F(LogWriterTest, RotatesBySizeIntoTimeSortedFilesWithManifests) {
  options_.max_file_bytes = 10'000;
  LogWriter w(options_);
  int64_t t = 0;
  write_events(w, 40, 1000, 0, &t);
  w.close();
  const std::vector<std::string> files = w.own_files();
  ASSERT_GE(files.size(), 4u);
  const std::vector<LogEvent> events = all_events(w);
  ASSERT_EQ(events.size(), 40u);
  for (size_t i = 0; i < events.size(); ++i) {
    EXPECT_EQ(events[i].event_number, static_cast<int64_t>(i));  // sorted names = time order
    EXPECT_EQ(events[i].data[0], static_cast<uint8_t>(i));
  }
  for (const std::string& f : files) {
    EXPECT_LE(fs::file_size(f), 10'000u + 1100u);
    ASSERT_TRUE(fs::exists(f + ".manifest.json")) << f;
  }
  std::ifstream in(files[0] + ".manifest.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["channels"]["CHAN"]["messages"], scan_log_file(files[0]).events.size());
  EXPECT_EQ(w.status().events_written, 40);
  EXPECT_EQ(w.status().files_closed, static_cast<int64_t>(files.size()));
}

TEST_F(LogWriterTest, RotatesByAge) {
  options_.max_file_duration_ns = 100 * kMs;
  LogWriter w(options_);
  int64_t t = 0;
  write_events(w, 35, 10, 0, &t);  // 340 ms
  w.close();
  EXPECT_EQ(w.own_files().size(), 4u);
  EXPECT_EQ(all_events(w).size(), 35u);
}

TEST_F(LogWriterTest, EventsOlderThanTheFlushPeriodAreOnDisk) {
  options_.flush_period_ns = 50 * kMs;
  LogWriter w(options_);
  int64_t t = 0;
  write_events(w, 20, 100, 0, &t);  // up to 190 ms
  // As a kill -9 would find the file now: everything up to the last flush (>= 150 ms).
  const LogScan scan = scan_log_file(w.status().current_file);
  EXPECT_GE(scan.events.size(), 16u);
  EXPECT_LT(scan.events.size(), 20u);  // the newest are still buffered
  EXPECT_EQ(scan.torn_tail_bytes, 0);
  w.poll(t + 60 * kMs);
  EXPECT_EQ(scan_log_file(w.status().current_file).events.size(), 20u);
}

TEST_F(LogWriterTest, DiskGuardStopsAndResumes) {
  options_.min_free_bytes = 1'000'000;
  int64_t free = 10'000'000;
  LogWriter w(options_, [&](const std::string&) { return free; });
  int64_t t = 0;
  write_events(w, 5, 100, 0, &t);
  w.poll(t + 100 * kMs);
  EXPECT_TRUE(w.status().recording);
  free = 900'000;  // below the minimum
  write_events(w, 10, 100, t + 200 * kMs, &t);
  EXPECT_FALSE(w.status().recording);
  EXPECT_NE(w.status().message.find("disk guard"), std::string::npos) << w.status().message;
  EXPECT_GT(w.status().events_dropped, 0);
  EXPECT_TRUE(w.status().current_file.empty());  // the file was closed with its manifest
  free = 5'000'000;
  w.poll(t + 2000 * kMs);  // checks again (at most once a second)
  EXPECT_TRUE(w.status().recording);
  write_events(w, 3, 100, t + 3000 * kMs, &t);
  w.close();
  EXPECT_EQ(all_events(w).size(), static_cast<size_t>(w.status().events_written));
  EXPECT_EQ(w.status().events_written + w.status().events_dropped, 18);
  EXPECT_EQ(w.own_files().size(), 2u);
}

TEST_F(LogWriterTest, DiskGuardDeletesOnlyItsOwnOldestFiles) {
  options_.on_disk_full = DiskFullPolicy::kDeleteOldest;
  options_.max_file_bytes = 2000;
  options_.min_free_bytes = 1'000'000;
  fs::create_directories(dir_);
  std::ofstream(dir_ + "/other-data.lcmlog") << "not ours";
  int64_t free = 10'000'000;
  LogWriter w(options_, [&](const std::string&) { return free; });
  int64_t t = 0;
  write_events(w, 20, 500, 0, &t);  // about 6 files
  const std::vector<std::string> before = w.own_files();
  ASSERT_GE(before.size(), 4u);
  // Each deletion frees what the deleted file held.
  free = 990'000;
  write_events(w, 1, 500, t + 100 * kMs, &t);
  w.poll(t + 200 * kMs);
  EXPECT_FALSE(w.status().recording);  // the fake free space never grows: all own files go
  EXPECT_EQ(w.status().files_deleted, static_cast<int64_t>(before.size()));
  EXPECT_TRUE(fs::exists(dir_ + "/other-data.lcmlog"));
  for (const std::string& f : before) EXPECT_FALSE(fs::exists(f + ".manifest.json"));
}

// A 256 kB tmpfs over the test directory, unmounted at scope exit.
class SmallFilesystem {
 public:
  explicit SmallFilesystem(const std::string& dir) : dir_(dir) {
    fs::create_directories(dir_);
    if (::mount("tmpfs", dir_.c_str(), "tmpfs", 0, "size=256k") == 0)
      mounted_ = true;
    else
      error_ = std::strerror(errno);
  }
  ~SmallFilesystem() {
    if (mounted_) ::umount2(dir_.c_str(), MNT_DETACH);
  }
  bool mounted() const { return mounted_; }
  const std::string& error() const { return error_; }

 private:
  std::string dir_, error_;
  bool mounted_ = false;
};

TEST_F(LogWriterTest, TheGuardStopsBeforeARealFilesystemIsFull) {
  const SmallFilesystem small(dir_);
  if (!small.mounted())
    GTEST_SKIP() << "cannot mount a small tmpfs here (needs root): " << small.error();
  options_.min_free_bytes = 64 << 10;
  LogWriter w(options_);
  int64_t t = 0;
  write_events(w, 60, 10'000, 0, &t);  // 600 kB into 256 kB
  w.poll(t + 100 * kMs);
  EXPECT_FALSE(w.status().recording);
  EXPECT_EQ(w.status().write_errors, 0);
  EXPECT_NE(w.status().message.find("disk guard"), std::string::npos) << w.status().message;
  EXPECT_GE(filesystem_free_bytes(dir_), 64 << 10);
  w.close();
  const std::vector<LogEvent> events = all_events(w);
  EXPECT_GT(events.size(), 5u);
  EXPECT_EQ(static_cast<int64_t>(events.size()) + w.status().events_dropped, 60);
}

TEST_F(LogWriterTest, ENospcStopsRecordingWithoutLosingWhatWasWritten) {
  const SmallFilesystem small(dir_);
  if (!small.mounted())
    GTEST_SKIP() << "cannot mount a small tmpfs here (needs root): " << small.error();
  // A filesystem that does not tell its free space: the kernel's ENOSPC must be handled.
  LogWriter w(options_, [](const std::string&) { return int64_t{-1}; });
  int64_t t = 0;
  write_events(w, 60, 10'000, 0, &t);
  w.poll(t + 100 * kMs);
  EXPECT_FALSE(w.status().recording);
  EXPECT_GT(w.status().write_errors, 0);
  EXPECT_NE(w.status().message.find("No space left"), std::string::npos) << w.status().message;
  w.close();
  // The file ends in at most one torn event; every complete one before it is readable.
  const std::vector<LogEvent> events = all_events(w);
  EXPECT_GT(events.size(), 10u);
  for (size_t i = 0; i < events.size(); ++i)
    EXPECT_EQ(events[i].event_number, static_cast<int64_t>(i));
  EXPECT_EQ(static_cast<int64_t>(events.size()), w.status().events_written);
  EXPECT_EQ(w.status().events_written + w.status().events_dropped, 60);
}

}  // namespace
}  // namespace hs
