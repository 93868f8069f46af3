// The multi-machine split (issue 9) on two network namespaces joined by a veth pair, LCM udpm
// with ttl=1 across it. Host A runs the replayed sensors (stock lcm-logplayer), the tracker and a
// recorder; host B the mapper and the logger. Against a run with everything on A, and with the
// link cut for 3 s in the middle (B's end downed: A sees NO-CARRIER, as with a pulled cable):
// the accuracy, B's recording of every message A sent outside the cut (and the cut as gaps in its
// manifest), the tracker publishing POSE alone during the cut, and the mapper's corrections
// resuming after it. Also the link bandwidth of raw vs PNG CAM_STEREO.
#include <gtest/gtest.h>
#include <signal.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <thread>

#include "common/lcm/decode.h"
#include "hsslam/odometry_t.hpp"
#include "hsslam/tracker_status_t.hpp"
#include "logger/lcm_log_format.h"
#include "logger/log_manifest.h"
#include "tests/common/ate_test_util.h"
#include "tests/common/child_process.h"
#include "tests/common/process_test_util.h"
#include "tests/common/sim_log_util.h"
#include "tests/common/two_hosts.h"
#include "tests/dataset/dataset_test_util.h"

namespace hs {
namespace {

namespace fs = std::filesystem;
using test::ChildProcess;
using test::TwoHosts;
using test::wait_for;

constexpr const char* kUrl = "udpm://239.255.76.67:7667?ttl=1&recv_buf_size=16777216";
constexpr int kDurationS = 16;
constexpr int kCutAfterS = 6, kCutForS = 3;

int64_t wall_us() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000 + ts.tv_nsec / 1000;
}

void sleep_s(double s) {
  std::this_thread::sleep_for(std::chrono::duration<double>(s));
}

// Every event of the .lcmlog files of a directory (a logger's output).
std::vector<LogEvent> read_logs(const std::string& dir) {
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".lcmlog") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  std::vector<LogEvent> events;
  for (const std::string& f : files) {
    LogScan scan = scan_log_file(f);
    for (LogEvent& e : scan.events) events.push_back(std::move(e));
  }
  return events;
}

nlohmann::json read_manifest(const std::string& dir) {
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().string().size() > 14 &&
        e.path().string().substr(e.path().string().size() - 14) == ".manifest.json")
      return nlohmann::json::parse(std::ifstream(e.path()));
  return {};
}

// The messages of one channel, by content (a multiset).
std::multiset<std::string> messages(const std::vector<LogEvent>& events, const std::string& ch) {
  std::multiset<std::string> out;
  for (const LogEvent& e : events)
    if (e.channel == ch) out.emplace(e.data.begin(), e.data.end());
  return out;
}

bool is_subset(const std::multiset<std::string>& part, const std::multiset<std::string>& whole) {
  return std::includes(whole.begin(), whole.end(), part.begin(), part.end());
}

int64_t counter(const hsslam::tracker_status_t& s, const std::string& name) {
  for (size_t i = 0; i < s.counter_names.size(); ++i)
    if (s.counter_names[i] == name) return s.counter_values[i];
  return -1;
}

class TwoHostSplit : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    const std::string d = dir_->path();
    ASSERT_TRUE(test::make_sim_log(HS_SIM, HS_EUROC2LCM, d, kDurationS));
    // A roomy frame queue: CI machines may stall the tracker while other jobs run.
    std::ofstream(d + "/node.yaml") << "node:\n  frame_queue_size: 100\n";
    // A's own recording, for what A sent (the replayed images are in sim.lcmlog already).
    std::ofstream(d + "/logger_a.yaml") << "logger:\n  exclude: [CAM_STEREO]\n";
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override {
    if (!hosts_.error().empty())
      GTEST_SKIP() << "two-host split not tested: cannot make network namespaces here ("
                   << hosts_.error() << ")";
  }

  static std::string d() { return dir_->path(); }
  std::unique_ptr<ChildProcess> start(const std::string& ns, std::vector<std::string> argv,
                                      const std::string& name) {
    return std::make_unique<ChildProcess>(TwoHosts::in(ns, std::move(argv)),
                                          d() + "/" + name + ".txt");
  }
  static bool says(ChildProcess& p, const std::string& word) {
    return wait_for([&] { return p.output().find(word) != std::string::npos; }, 20);
  }
  static void stop(ChildProcess& p) {
    p.signal(SIGINT);
    EXPECT_EQ(p.wait(), 0) << p.output();
  }

  // Replays the dataset on A with the tracker and a POSE recorder there, the mapper on
  // `mapper_host`; with `split`, loggers on both hosts; with `cut`, the link cut in the middle.
  // `speed` is the replay's (lcm-logplayer -s). Returns the ATE.
  double run(const std::string& name, const std::string& mapper_host, bool split, bool cut,
             const std::string& speed) {
    const std::string out = d() + "/" + name;
    fs::create_directories(out);
    const std::string A = hosts_.a(), B = hosts_.b();
    auto recorder = start(A,
                          {HS_RECORD_TRAJECTORY, "--channel", "POSE", "--out", out + "/pose.tum",
                           "--lcm-url", kUrl, "--idle-timeout", "5"},
                          name + "_recorder");
    auto tracker = start(
        A, {HS_TRACKER, "--config", d() + "/node.yaml", "--calib", d() + "/sim", "--lcm-url", kUrl},
        name + "_tracker");
    auto mapper = start(mapper_host, {HS_MAPPER, "--calib", d() + "/sim", "--lcm-url", kUrl},
                        name + "_mapper");
    std::unique_ptr<ChildProcess> logger_a, logger_b;
    if (split) {
      logger_a = start(A,
                       {HS_LOGGER, "--config", d() + "/logger_a.yaml", "--dir", out + "/logs_a",
                        "--lcm-url", kUrl},
                       name + "_logger_a");
      logger_b =
          start(B, {HS_LOGGER, "--dir", out + "/logs_b", "--lcm-url", kUrl}, name + "_logger_b");
      EXPECT_TRUE(says(*logger_a, "recording")) << logger_a->output();
      EXPECT_TRUE(says(*logger_b, "recording")) << logger_b->output();
    }
    EXPECT_TRUE(says(*tracker, "listening")) << tracker->output();
    EXPECT_TRUE(says(*mapper, "listening")) << mapper->output();
    EXPECT_TRUE(says(*recorder, "recording")) << recorder->output();
    auto player =
        start(A, {"lcm-logplayer", "-s", speed, "-l", kUrl, d() + "/sim.lcmlog"}, name + "_player");
    if (cut) {
      sleep_s(kCutAfterS);
      cut_us_ = wall_us();
      EXPECT_TRUE(hosts_.cut());
      sleep_s(kCutForS);
      EXPECT_TRUE(hosts_.restore());
      restore_us_ = wall_us();
    }
    const int replay_s = static_cast<int>(kDurationS / std::stod(speed));
    EXPECT_TRUE(wait_for([&] { return !player->running(); }, 3 * replay_s));
    EXPECT_EQ(player->wait(), 0) << player->output();
    EXPECT_EQ(recorder->wait(), 0) << recorder->output();  // after 5 s without POSE
    stop(*tracker);
    stop(*mapper);
    if (split) {
      stop(*logger_a);
      stop(*logger_b);
    }
    std::printf("%s:\n%s%s", name.c_str(), tracker->output().c_str(), mapper->output().c_str());
    return test::ate_rmse(HS_EVAL, d() + "/sim/mav0/state_groundtruth_estimate0/data.csv",
                          out + "/pose.tum", out + "/eval.json");
  }

  static void expect_b_recorded_what_a_sent(const std::string& run_dir,
                                            const std::vector<LogEvent>& a,
                                            const std::vector<LogEvent>& b, double cut_s);

  static test::TempDir* dir_;
  TwoHosts hosts_;
  int64_t cut_us_ = 0, restore_us_ = 0;
};

test::TempDir* TwoHostSplit::dir_ = nullptr;

// What B recorded against what A sent, for the channels A publishes: every message outside the
// cut, and as many missing as B's manifest reports lost upstream, in one gap per sequenced
// channel (none without a cut).
void TwoHostSplit::expect_b_recorded_what_a_sent(const std::string& run_dir,
                                                 const std::vector<LogEvent>& a,
                                                 const std::vector<LogEvent>& b, double cut_s) {
  const std::vector<LogEvent> replayed = scan_log_file(d() + "/sim.lcmlog").events;
  const nlohmann::json manifest = read_manifest(run_dir + "/logs_b");
  ASSERT_FALSE(manifest.empty()) << "no manifest in " << run_dir << "/logs_b";
  for (const auto& [channel, rate_hz, source] :
       std::vector<std::tuple<std::string, double, const std::vector<LogEvent>*>>{
           {"CAM_STEREO", 20, &replayed},
           {"IMU", 0, &replayed},
           {"POSE", 20, &a},
           {"TRACKER_STATUS", 20, &a}}) {
    const std::multiset<std::string> sent = messages(*source, channel);
    const std::multiset<std::string> got = messages(b, channel);
    const nlohmann::json& c = manifest["channels"][channel];
    ASSERT_FALSE(c.is_null()) << channel;
    const int64_t lost = c["lost_upstream"].get<int64_t>();
    std::printf("%-15s A sent %zu, B recorded %zu, B's manifest: %lld lost upstream in %zu gaps\n",
                channel.c_str(), sent.size(), got.size(), static_cast<long long>(lost),
                c["gaps"].size());
    EXPECT_TRUE(is_subset(got, sent)) << channel << ": B holds messages A never sent";
    EXPECT_EQ(static_cast<int64_t>(sent.size() - got.size()), lost) << channel;
    EXPECT_EQ(c["gaps"].size(), cut_s > 0 ? 1u : 0u) << channel << ": " << c["gaps"].dump();
    if (rate_hz > 0 && cut_s > 0) {  // about the cut's worth of messages
      EXPECT_GE(lost, 0.7 * cut_s * rate_hz) << channel;
      EXPECT_LE(lost, 1.5 * cut_s * rate_hz + 10) << channel;
    }
  }
}

TEST_F(TwoHostSplit, MapperAndLoggerOnASecondHost) {
  // At half speed: the mapper's corrections come within a frame on a busy host too, so the
  // comparison is of the split, not of how late a slowed mapper's corrections arrive (the
  // corrections move the pose by about half the ATE; see the mapper process test).
  // Each configuration runs twice, alternately, and their means are compared: both are processes
  // whose corrections land a frame earlier or later from run to run, which moves one run's ATE
  // by 0.2-0.3 mm (standard deviation; over six runs each, single host 1.6-2.0 mm, split
  // 1.6-2.4 mm). One such deviation, 0.3 mm, is allowed on top of the 10%.
  double single = 0, split = 0;
  for (const std::string suffix : {"", "_2"}) {
    single += 0.5 * run("single" + suffix, hosts_.a(), false, false, "0.5");
    split += 0.5 * run("split" + suffix, hosts_.b(), true, false, "0.5");
  }
  std::printf("ATE single host %.4f m, split over the link %.4f m (%.2fx), means of two runs\n",
              single, split, split / single);
  EXPECT_LE(split, 1.1 * single + 0.0003) << "the issue allows 10%";
  const std::vector<LogEvent> a = read_logs(d() + "/split/logs_a");
  const std::vector<LogEvent> b = read_logs(d() + "/split/logs_b");
  expect_b_recorded_what_a_sent(d() + "/split", a, b, 0);
  EXPECT_EQ(messages(b, "KEYFRAME"), messages(a, "KEYFRAME"));
  EXPECT_EQ(messages(b, "MAP_UPDATE"), messages(a, "MAP_UPDATE"));
  // The tracker on A applied the corrections that came over the link.
  int64_t applied = -1;
  for (const LogEvent& e : a) {
    if (e.channel == "TRACKER_STATUS")
      applied = counter(
          decode_message<hsslam::tracker_status_t>(e.data.data(), e.data.size(), "TRACKER_STATUS"),
          "corrections_applied");
  }
  const auto updates = static_cast<int64_t>(messages(a, "MAP_UPDATE").size());
  std::printf("MAP_UPDATE on A: %lld, corrections applied: %lld\n", static_cast<long long>(updates),
              static_cast<long long>(applied));
  EXPECT_GE(applied, updates * 8 / 10);
  // What each channel needs of the link (B's manifest: bytes over the recording's span).
  const nlohmann::json manifest = read_manifest(d() + "/split/logs_b");
  const double span_s = manifest["duration_s"].get<double>();
  for (const auto& [channel, c] : manifest["channels"].items())
    std::printf("  %-15s %6lld messages %9.3f MB/s\n", channel.c_str(),
                static_cast<long long>(c["messages"].get<int64_t>()),
                static_cast<double>(c["bytes"].get<int64_t>()) / span_s / 1e6);
}

TEST_F(TwoHostSplit, TheLinkCutFor3sLeavesTheTrackerAloneAndTheMapperResynchronises) {
  const double ate = run("cut", hosts_.b(), true, true, "1");
  const double cut_s = 1e-6 * static_cast<double>(restore_us_ - cut_us_);
  std::printf("ATE with the link cut for %.2f s: %.4f m\n", cut_s, ate);
  const std::vector<LogEvent> a = read_logs(d() + "/cut/logs_a");
  const std::vector<LogEvent> b = read_logs(d() + "/cut/logs_b");
  expect_b_recorded_what_a_sent(d() + "/cut", a, b, cut_s);
  // KEYFRAME carries no seq: every one A recorded outside the cut (with a margin for messages
  // in flight) is in B's recording.
  const std::multiset<std::string> b_keyframes = messages(b, "KEYFRAME");
  int keyframes_outside = 0;
  for (const LogEvent& e : a) {
    if (e.channel != "KEYFRAME" ||
        (e.utime > cut_us_ - 200'000 && e.utime < restore_us_ + 1'000'000))
      continue;
    ++keyframes_outside;
    EXPECT_TRUE(b_keyframes.count(std::string(e.data.begin(), e.data.end())))
        << "KEYFRAME at " << e.utime << " missing on B";
  }
  EXPECT_GT(keyframes_outside, 10);

  // A's tracker went on alone during the cut: POSE at the frame rate, tracked.
  int poses_in_cut = 0;
  int64_t last_pose_us = 0, longest_gap_us = 0;
  for (const LogEvent& e : a) {
    if (e.channel != "POSE") continue;
    if (last_pose_us) longest_gap_us = std::max(longest_gap_us, e.utime - last_pose_us);
    last_pose_us = e.utime;
    if (e.utime < cut_us_ || e.utime > restore_us_) continue;
    ++poses_in_cut;
    const auto pose = decode_message<hsslam::odometry_t>(e.data.data(), e.data.size(), "POSE");
    EXPECT_GT(pose.quality, 0.0f) << "a frame during the cut was not tracked";
  }
  std::printf("POSE on A during the %.2f s cut: %d, longest gap between POSE %.0f ms\n", cut_s,
              poses_in_cut, 1e-3 * static_cast<double>(longest_gap_us));
  EXPECT_GE(poses_in_cut, 0.8 * cut_s * 20);
  EXPECT_LT(longest_gap_us, 300'000);

  // The mapper resynchronised: its corrections reach A again after the link returns and the
  // tracker applies them.
  int updates_after = 0;
  int64_t applied_at_restore = -1, applied_at_end = -1;
  for (const LogEvent& e : a) {
    if (e.channel == "MAP_UPDATE" && e.utime > restore_us_) ++updates_after;
    if (e.channel != "TRACKER_STATUS") continue;
    const auto s =
        decode_message<hsslam::tracker_status_t>(e.data.data(), e.data.size(), "TRACKER_STATUS");
    if (e.utime <= restore_us_) applied_at_restore = counter(s, "corrections_applied");
    applied_at_end = counter(s, "corrections_applied");
  }
  std::printf(
      "MAP_UPDATE on A after the link returned: %d; corrections applied %lld at the "
      "restore, %lld at the end\n",
      updates_after, static_cast<long long>(applied_at_restore),
      static_cast<long long>(applied_at_end));
  EXPECT_GE(updates_after, 3);
  EXPECT_GE(applied_at_end - applied_at_restore, 3);
}

// Raw vs PNG CAM_STEREO on the link, measured as the bytes B's end receives while A replays
// only CAM_STEREO: real EuRoC frames (../shared/data's 95 static V1_01 pairs, else the bundled
// 6), whose texture decides what PNG saves. Printed as MB/s at 20 Hz.
TEST_F(TwoHostSplit, CamStereoBandwidthRawVsPng) {
  const std::string real = test::kSharedEuroc + "/V1_01_static_stereo";
  const std::string dataset = fs::exists(real) ? real : test::kSampleRoot;
  std::map<std::string, double> mb_per_s;
  for (const std::string encoding : {"mono8", "png"}) {
    const std::string log = d() + "/real_" + encoding + ".lcmlog";
    ChildProcess conv({HS_EUROC2LCM, "--dataset", dataset, "--out", log, "--encoding", encoding},
                      log + ".txt");
    ASSERT_EQ(conv.wait(), 0) << conv.output();
    const size_t frames = messages(scan_log_file(log).events, "CAM_STEREO").size();
    ASSERT_GT(frames, 0u);
    const uint64_t before = hosts_.b_rx_bytes();
    auto player = start(hosts_.a(), {"lcm-logplayer", "-l", kUrl, "-e", "CAM_STEREO", log},
                        "player_" + encoding);
    ASSERT_TRUE(wait_for([&] { return !player->running(); }, 60));
    ASSERT_EQ(player->wait(), 0) << player->output();
    sleep_s(0.2);  // the last frame's fragments drained
    const double per_frame = static_cast<double>(hosts_.b_rx_bytes() - before) / frames;
    mb_per_s[encoding] = per_frame * 20 / 1e6;
    std::printf(
        "CAM_STEREO %-5s %zu stereo frames of %s: %.0f kB per frame on the link, "
        "%.2f MB/s at 20 Hz\n",
        encoding.c_str(), frames, dataset.c_str(), per_frame / 1e3, mb_per_s[encoding]);
  }
  // Raw is the two 752x480 images and little more (UDP/IP and LCM fragment headers).
  EXPECT_GE(mb_per_s["mono8"], 2 * 752 * 480 * 20 / 1e6);
  EXPECT_LE(mb_per_s["mono8"], 1.05 * 2 * 752 * 480 * 20 / 1e6);
  EXPECT_LT(mb_per_s["png"], 0.9 * mb_per_s["mono8"]);
  std::printf("PNG saves %.0f%% of the link\n", 100 * (1 - mb_per_s["png"] / mb_per_s["mono8"]));
}

}  // namespace
}  // namespace hs
