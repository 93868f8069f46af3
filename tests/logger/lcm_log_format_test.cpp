// The log format against the LCM library's own reader (the code lcm-logplayer runs), and the
// scanner's recovery from what crashes leave: a torn last event, damaged bytes mid-file.
#include "logger/lcm_log_format.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>

#include "common/core/error.h"

namespace hs {
namespace {

std::vector<LogEvent> sample_events() {
  std::vector<LogEvent> events;
  for (int i = 0; i < 5; ++i) {
    LogEvent e;
    e.event_number = i;
    e.utime = 1'700'000'000'000'000 + 50'000 * i;
    e.channel = i % 2 ? "IMU" : "CAM_STEREO";
    e.data.assign(static_cast<size_t>(100 + 1000 * i), static_cast<uint8_t>(i * 37 + 1));
    events.push_back(e);
  }
  return events;
}

class LcmLogFormatTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = (std::filesystem::temp_directory_path() /
             ("hs_log_format_" + std::to_string(::getpid()) + ".lcmlog"))
                .string();
    for (const LogEvent& e : events_) append_log_event(e, &bytes_);
  }
  void TearDown() override { std::filesystem::remove(path_); }
  void write(const std::vector<uint8_t>& bytes) const {
    std::ofstream(path_, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
  }
  static void expect_same(const LogEvent& a, const LogEvent& b) {
    EXPECT_EQ(a.event_number, b.event_number);
    EXPECT_EQ(a.utime, b.utime);
    EXPECT_EQ(a.channel, b.channel);
    EXPECT_EQ(a.data, b.data);
  }

  std::vector<LogEvent> events_ = sample_events();
  std::vector<uint8_t> bytes_;
  std::string path_;
};

TEST_F(LcmLogFormatTest, TheLcmLibraryReadsWhatWeWrite) {
  write(bytes_);
  lcm::LogFile log(path_, "r");
  ASSERT_TRUE(log.good());
  for (const LogEvent& e : events_) {
    const lcm::LogEvent* got = log.readNextEvent();
    ASSERT_NE(got, nullptr);
    EXPECT_EQ(got->eventnum, e.event_number);
    EXPECT_EQ(got->timestamp, e.utime);
    EXPECT_EQ(got->channel, e.channel);
    ASSERT_EQ(got->datalen, static_cast<int32_t>(e.data.size()));
    EXPECT_EQ(std::memcmp(got->data, e.data.data(), e.data.size()), 0);
  }
  EXPECT_EQ(log.readNextEvent(), nullptr);
}

TEST_F(LcmLogFormatTest, WeReadWhatTheLcmLibraryWrites) {
  {
    lcm::LogFile log(path_, "w");
    for (const LogEvent& e : events_) {
      lcm::LogEvent le{};
      le.eventnum = e.event_number;
      le.timestamp = e.utime;
      le.channel = e.channel;
      le.datalen = static_cast<int32_t>(e.data.size());
      le.data = const_cast<uint8_t*>(e.data.data());
      ASSERT_EQ(log.writeEvent(&le), 0);
    }
  }
  const LogScan scan = scan_log_file(path_);
  ASSERT_EQ(scan.events.size(), events_.size());
  for (size_t i = 0; i < events_.size(); ++i) expect_same(scan.events[i], events_[i]);
  EXPECT_EQ(scan.torn_tail_bytes, 0);
  EXPECT_EQ(scan.skipped_bytes, 0);
}

TEST_F(LcmLogFormatTest, ATornLastEventIsSkippedAtAnyCut) {
  // Cut inside the last event's header, channel and data: the first four always survive.
  size_t last_start = bytes_.size() - (kLcmLogHeaderSize + events_.back().channel.size() +
                                       events_.back().data.size());
  for (const size_t keep :
       {last_start + 3, last_start + 20, last_start + kLcmLogHeaderSize + 2, bytes_.size() - 1}) {
    write(std::vector<uint8_t>(bytes_.begin(), bytes_.begin() + static_cast<long>(keep)));
    const LogScan scan = scan_log_file(path_);
    ASSERT_EQ(scan.events.size(), events_.size() - 1) << "cut at " << keep;
    EXPECT_EQ(scan.torn_tail_bytes, static_cast<int64_t>(keep - last_start));
    EXPECT_EQ(scan.skipped_bytes, 0);
    expect_same(scan.events.back(), events_[events_.size() - 2]);
  }
}

TEST_F(LcmLogFormatTest, DamagedBytesMidFileAreSkippedToTheNextEvent) {
  std::vector<uint8_t> damaged = bytes_;
  const size_t second = kLcmLogHeaderSize + events_[0].channel.size() + events_[0].data.size();
  // Overwrite the second event's sync word and length fields, and insert junk after the third.
  damaged[second] ^= 0xFF;
  damaged[second + 21] = 0x7F;
  const size_t fourth = second + kLcmLogHeaderSize + events_[1].channel.size() +
                        events_[1].data.size() + kLcmLogHeaderSize + events_[2].channel.size() +
                        events_[2].data.size();
  damaged.insert(damaged.begin() + static_cast<long>(fourth), 57, 0xED);
  write(damaged);
  const LogScan scan = scan_log_file(path_);
  ASSERT_EQ(scan.events.size(), events_.size() - 1);  // the second is lost
  EXPECT_EQ(scan.skipped_regions, 2);
  EXPECT_EQ(scan.skipped_bytes, static_cast<int64_t>(kLcmLogHeaderSize + events_[1].channel.size() +
                                                     events_[1].data.size() + 57));
  EXPECT_EQ(scan.torn_tail_bytes, 0);
  expect_same(scan.events[1], events_[2]);
  expect_same(scan.events[2], events_[3]);
}

TEST_F(LcmLogFormatTest, AMissingFileIsAnInputError) {
  EXPECT_THROW(scan_log_file(path_ + ".missing"), InputError);
}

}  // namespace
}  // namespace hs
