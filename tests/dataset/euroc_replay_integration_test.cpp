// End to end over real processes and udpm multicast on loopback: hs-euroc2lcm writes a log,
// stock lcm-logplayer replays it, and a subscriber in this test, stock lcm-logger and
// hs-record-trajectory must receive every message byte-exact.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <thread>

#include "common/core/csv.h"
#include "common/lcm/lcm_connection.h"
#include "tests/common/child_process.h"
#include "tests/dataset/dataset_test_util.h"

namespace hs {
namespace {

namespace fs = std::filesystem;
using ::testing::ContainsRegex;
using ::testing::HasSubstr;

struct Event {
  std::string channel;
  std::vector<uint8_t> data;
  bool operator==(const Event& o) const { return channel == o.channel && data == o.data; }
};

constexpr const char* kSyncChannel = "HS_TEST_SYNC";
// LCM's udpm provider publishes this when an instance starts receiving; not replay traffic.
bool is_replay_channel(const std::string& channel) {
  return channel != kSyncChannel && channel != "LCM_SELF_TEST";
}

using Child = test::ChildProcess;

std::string read_text(const std::string& path) {
  std::string all;
  for (const std::string& l : test::read_lines(path)) all += l + "\n";
  return all;
}

std::vector<Event> read_log(const std::string& path) {
  lcm::LogFile log(path, "r");
  EXPECT_TRUE(log.good()) << path;
  std::vector<Event> events;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    if (!is_replay_channel(e->channel)) continue;
    const auto* p = static_cast<const uint8_t*>(e->data);
    events.push_back({e->channel, std::vector<uint8_t>(p, p + e->datalen)});
  }
  return events;
}

// hs-record-trajectory prints "recording ..." once it has subscribed.
bool recorder_ready(const std::string& output) {
  return read_text(output).find("recording") != std::string::npos;
}

struct Collector {
  std::vector<Event> events;
  int sync = 0;
  static void on(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Collector* self) {
    if (channel == kSyncChannel) ++self->sync;
    if (!is_replay_channel(channel)) return;
    const auto* p = static_cast<const uint8_t*>(rbuf->data);
    self->events.push_back({channel, std::vector<uint8_t>(p, p + rbuf->data_size)});
  }
};

class EurocReplay : public ::testing::Test {
 protected:
  void SetUp() override {
    const long long rmem = read_rmem_max();
    ASSERT_GE(rmem, kWantedReceiveBuffer)
        << "net.core.rmem_max is " << rmem << " bytes: large LCM messages would be lost over "
        << "udpm. Run tools/setup.sh as root (it sets net.core.rmem_max and rmem_default to "
        << "16777216 and adds the multicast route 224.0.0.0/4 dev lo).";
    // A port of our own so parallel test runs (and live processes on 7667) never cross-talk.
    url_ = "udpm://239.255.76.67:" + std::to_string(20000 + ::getpid() % 40000) +
           "?ttl=0&recv_buf_size=16777216";
    lcm_ = std::make_unique<lcm::LCM>(url_);
    ASSERT_TRUE(lcm_->good()) << "cannot open " << url_
                              << ": no multicast route? Run tools/setup.sh as root (or "
                                 "`ip route add 224.0.0.0/4 dev lo`).";
    lcm_->subscribeFunction(".*", &Collector::on, &collector_);
  }

  // The shared real sequence when present, else the bundled sample.
  static std::string dataset() {
    const std::string shared = test::kSharedEuroc + "/V1_01_static_stereo";
    if (fs::exists(shared)) return shared;
    std::printf("note: %s absent; replaying the bundled sample\n", shared.c_str());
    return test::kSampleRoot;
  }

  std::string convert(const std::string& root) {
    const std::string log = dir_.path() + "/replay.lcmlog";
    Child c({HS_EUROC2LCM, "--dataset", root, "--out", log}, dir_.path() + "/euroc2lcm.txt");
    EXPECT_EQ(c.wait(), 0) << read_text(dir_.path() + "/euroc2lcm.txt");
    return log;
  }

  // Publishes a sync message every 100 ms until `ready()` (a process has subscribed); false
  // after 20 s.
  template <class Ready>
  bool wait_until_listening(Ready&& ready) {
    using Clock = std::chrono::steady_clock;
    const auto deadline = Clock::now() + std::chrono::seconds(20);
    auto next_sync = Clock::now();
    while (Clock::now() < deadline) {
      if (ready()) return true;
      if (Clock::now() >= next_sync) {
        lcm_->publish(kSyncChannel, "x", 1);
        next_sync += std::chrono::milliseconds(100);
      }
      lcm_->handleTimeout(20);
    }
    return false;
  }

  // Handles messages until `expected` have arrived, or `player` has exited and nothing came
  // for 3 s (then the comparison below reports what is missing).
  void receive(size_t expected, Child& player) {
    auto last = std::chrono::steady_clock::now();
    while (collector_.events.size() < expected) {
      if (lcm_->handleTimeout(100) > 0) last = std::chrono::steady_clock::now();
      if (!player.running() && std::chrono::steady_clock::now() - last > std::chrono::seconds(3))
        break;
    }
  }

  test::TempDir dir_;
  std::string url_;
  std::unique_ptr<lcm::LCM> lcm_;
  Collector collector_;
};

void expect_same_events(const std::vector<Event>& got, const std::vector<Event>& want,
                        const std::string& who) {
  EXPECT_EQ(got.size(), want.size()) << who;
  for (size_t i = 0; i < std::min(got.size(), want.size()); ++i)
    if (!(got[i] == want[i])) {
      ADD_FAILURE() << who << ": event " << i << " differs (channel " << got[i].channel << " vs "
                    << want[i].channel << ", " << got[i].data.size() << " vs "
                    << want[i].data.size() << " bytes)";
      return;
    }
}

TEST_F(EurocReplay, LogplayerToSubscriberAndLcmLoggerIsByteExact) {
  const std::string log = convert(dataset());
  const std::vector<Event> want = read_log(log);
  ASSERT_FALSE(want.empty());
  size_t bytes = 0;
  for (const Event& e : want) bytes += e.data.size();
  std::printf("replaying %zu events, %.1f MB over %s\n", want.size(), bytes / 1e6, url_.c_str());

  const std::string logged = dir_.path() + "/logger.lcmlog";
  Child logger({"lcm-logger", "--lcm-url=" + url_, "--flush-interval=20", "-f", logged},
               dir_.path() + "/logger.txt");
  ASSERT_TRUE(logger.started());
  ASSERT_TRUE(wait_until_listening([&] {
    std::error_code ec;
    return collector_.sync > 0 && fs::file_size(logged, ec) > 0 && !ec;
  })) << "lcm-logger did not log: "
      << read_text(dir_.path() + "/logger.txt");

  Child player({"lcm-logplayer", "-l", url_, log}, dir_.path() + "/player.txt");
  ASSERT_TRUE(player.started());
  receive(want.size(), player);
  EXPECT_EQ(player.wait(), 0) << read_text(dir_.path() + "/player.txt");
  expect_same_events(collector_.events, want, "subscriber");

  logger.signal(SIGINT);
  EXPECT_EQ(logger.wait(), 0) << read_text(dir_.path() + "/logger.txt");
  expect_same_events(read_log(logged), want, "lcm-logger");
}

TEST_F(EurocReplay, RecordGroundTruthToTum) {
  const std::string root = test::kSampleRoot;
  const std::string log = convert(root);
  const std::string tum = dir_.path() + "/gt.tum";
  const std::string out = dir_.path() + "/recorder.txt";
  const std::vector<std::string> gt_rows =
      test::read_lines(root + "/mav0/state_groundtruth_estimate0/data.csv");
  const size_t n_gt = gt_rows.size() - 1;  // minus the header
  Child recorder({HS_RECORD_TRAJECTORY, "--channel", "GROUND_TRUTH", "--out", tum, "--lcm-url",
                  url_, "--count", std::to_string(n_gt), "--idle-timeout", "60"},
                 out);
  ASSERT_TRUE(wait_until_listening([&] { return recorder_ready(out); })) << read_text(out);

  Child player({"lcm-logplayer", "-l", url_, log}, dir_.path() + "/player.txt");
  EXPECT_EQ(player.wait(), 0);
  ASSERT_EQ(recorder.wait(), 0) << read_text(out);
  const std::string report = read_text(out);
  EXPECT_THAT(report, HasSubstr("wrote " + std::to_string(n_gt) + " ground_truth_t poses"));
  // It counted every message up to the last ground-truth state, per channel.
  std::map<std::string, int> heard;
  for (const Event& e : read_log(log)) {
    ++heard[e.channel];
    if (heard["GROUND_TRUTH"] == static_cast<int>(n_gt)) break;
  }
  for (const auto& [channel, n] : heard) {
    EXPECT_THAT(report, ContainsRegex("\n  " + channel + " +" + std::to_string(n) + "\n"));
  }

  // Each TUM row is the EuRoC row: same time (exact), position and quaternion.
  CsvReader csv(root + "/mav0/state_groundtruth_estimate0/data.csv");
  CsvReader est(tum, " ");
  CsvRow g, e;
  size_t rows = 0;
  while (csv.next(g)) {
    ASSERT_TRUE(est.next(e));
    ++rows;
    const std::string t = g.fields[0];
    EXPECT_EQ(e.fields[0], t.substr(0, t.size() - 9) + "." + t.substr(t.size() - 9));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(est.double_at(e, 1 + i), csv.double_at(g, 1 + i), 1e-9);
    const double sign = est.double_at(e, 7) * csv.double_at(g, 4) < 0 ? -1.0 : 1.0;
    EXPECT_NEAR(sign * est.double_at(e, 7), csv.double_at(g, 4), 1e-5);  // qw
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(sign * est.double_at(e, 4 + i), csv.double_at(g, 5 + i), 1e-5);  // qx qy qz
  }
  EXPECT_EQ(rows, n_gt);
  EXPECT_FALSE(est.next(e));
}

TEST_F(EurocReplay, RecorderStopsOnSignalOrIdleAndWritesNothingWithoutPoses) {
  const std::string tum = dir_.path() + "/none.tum";
  {
    const std::string out = dir_.path() + "/sig.txt";
    Child recorder({HS_RECORD_TRAJECTORY, "--channel", "POSE", "--out", tum, "--lcm-url", url_},
                   out);
    ASSERT_TRUE(wait_until_listening([&] { return recorder_ready(out); })) << read_text(out);
    recorder.signal(SIGTERM);
    EXPECT_EQ(recorder.wait(), 1);
    EXPECT_THAT(read_text(out), HasSubstr("no pose received on POSE"));
  }
  {
    const std::string out = dir_.path() + "/idle.txt";
    Child recorder({HS_RECORD_TRAJECTORY, "--channel", "POSE", "--out", tum, "--lcm-url", url_,
                    "--idle-timeout", "0.3"},
                   out);
    EXPECT_EQ(recorder.wait(), 1);
    EXPECT_THAT(read_text(out), HasSubstr("no pose received"));
  }
  EXPECT_FALSE(fs::exists(tum));
}

TEST(Euroc2lcmCli, BadInputExitsNonZeroNamingFileLineAndWritesNothing) {
  test::SampleCopy ds;
  test::edit_line(ds.mav0() + "/imu0/data.csv", 5, "1403715273277143040,0.1,nan,0,0,0,0");
  const test::TempDir dir;
  const std::string out = dir.path() + "/out.lcmlog", text = dir.path() + "/out.txt";
  Child c({HS_EUROC2LCM, "--dataset", ds.root(), "--out", out}, text);
  EXPECT_EQ(c.wait(), 1);
  EXPECT_THAT(read_text(text), HasSubstr(ds.mav0() + "/imu0/data.csv:5: column 3"));
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace hs
