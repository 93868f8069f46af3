// The end-to-end test over real processes and udpm multicast on loopback: hs-sim writes
// a room_mav dataset, hs-euroc2lcm converts it, stock lcm-logplayer replays it at 1x to the
// hs-tracker process, hs-record-trajectory records POSE, and the trajectory must equal hs-run's
// on the same folder (same frames, same positions).
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Core>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <thread>

#include "common/core/csv.h"
#include "common/core/types.h"
#include "common/lcm/decode.h"
#include "common/lcm/lcm_connection.h"
#include "hsslam/heartbeat_t.hpp"
#include "hsslam/odometry_t.hpp"
#include "hsslam/tracker_status_t.hpp"
#include "tests/common/child_process.h"
#include "tests/common/process_test_util.h"
#include "tests/dataset/dataset_test_util.h"

namespace hs {
namespace {

namespace fs = std::filesystem;
using test::ChildProcess;
using test::wait_for;

struct TumPose {
  std::string t;  // as written: exact
  Eigen::Vector3d p;
};

std::vector<TumPose> read_tum(const std::string& path) {
  CsvReader csv(path, " ");
  std::vector<TumPose> out;
  CsvRow row;
  while (csv.next(row))
    out.push_back({row.fields[0], Eigen::Vector3d(csv.double_at(row, 1), csv.double_at(row, 2),
                                                  csv.double_at(row, 3))});
  return out;
}

// What the test hears from hs-tracker besides POSE.
struct Heard {
  std::vector<int64_t> pose_imu_t_ns;
  std::vector<std::chrono::steady_clock::time_point> pose_imu_arrival;
  int64_t statuses = 0;
  int64_t dropped = 0;  // frames_dropped_queue_full of the latest status
  int32_t max_frame_queue = 0;
  static void on(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Heard* self) {
    try {
      if (channel == "POSE_IMU") {
        self->pose_imu_t_ns.push_back(
            decode_message<hsslam::odometry_t>(rbuf->data, rbuf->data_size, channel).t_ns);
        self->pose_imu_arrival.push_back(std::chrono::steady_clock::now());
      } else if (channel == "TRACKER_STATUS") {
        const auto s =
            decode_message<hsslam::tracker_status_t>(rbuf->data, rbuf->data_size, channel);
        ++self->statuses;
        for (int i = 0; i < s.num_counters; ++i)
          if (s.counter_names[i] == "frames_dropped_queue_full")
            self->dropped = s.counter_values[i];
      } else if (channel == "HEARTBEAT") {
        const auto h = decode_message<hsslam::heartbeat_t>(rbuf->data, rbuf->data_size, channel);
        if (!h.queue_depths.empty())
          self->max_frame_queue = std::max(self->max_frame_queue, h.queue_depths[0]);
      }
    } catch (const std::exception& e) {
      ADD_FAILURE() << e.what();
    }
  }
};

// The rig under test: its hs-run flags and hs-tracker config, and the room_mav seconds to run.
struct Rig {
  std::vector<std::string> run_flags;
  std::string tracker_yaml;
  const char* duration_s;
};

void expect_replay_matches_offline_run(const Rig& rig) {
  const long long rmem = read_rmem_max();
  ASSERT_GE(rmem, kWantedReceiveBuffer)
      << "net.core.rmem_max is " << rmem << " bytes: camera frames would be lost over udpm. Run "
      << "tools/setup.sh as root (rmem_max/rmem_default 16777216, route 224.0.0.0/4 dev lo).";
  const std::string url = test::private_udpm_url();
  lcm::LCM lcm(url);
  ASSERT_TRUE(lcm.good()) << "cannot open " << url << ": no multicast route? Run tools/setup.sh";
  Heard heard;
  lcm.subscribeFunction("POSE_IMU|TRACKER_STATUS|HEARTBEAT", &Heard::on, &heard);

  const test::TempDir dir;
  const std::string d = dir.path(), sim = d + "/sim", log = d + "/sim.lcmlog";
  ChildProcess gen({HS_SIM, "--scenario", HS_SOURCE_DIR "/config/sim/room_mav.yaml", "--out", sim,
                    "--duration", rig.duration_s, "--quiet"},
                   d + "/sim.txt");
  ASSERT_EQ(gen.wait(), 0) << gen.output();
  // One IMU sample per message, as a driver sends them: POSE_IMU can then show the IMU rate.
  ChildProcess conv({HS_EUROC2LCM, "--dataset", sim, "--out", log, "--imu-batch", "1"},
                    d + "/euroc2lcm.txt");
  ASSERT_EQ(conv.wait(), 0) << conv.output();
  std::vector<std::string> run_args{HS_RUN, "--dataset", sim, "--out", d + "/run"};
  run_args.insert(run_args.end(), rig.run_flags.begin(), rig.run_flags.end());
  ChildProcess run(run_args, d + "/run.txt");
  ASSERT_EQ(run.wait(), 0) << run.output();
  const std::vector<TumPose> want = read_tum(d + "/run/trajectory.tum");
  ASSERT_GT(want.size(), 100u) << run.output();

  // A roomy frame queue: this checks equivalence, and CI machines may stall the tracker for
  // longer than two frames (the default) while other jobs run.
  std::ofstream(d + "/node.yaml") << "node:\n  frame_queue_size: 100\n" << rig.tracker_yaml;
  ChildProcess recorder(
      {HS_RECORD_TRAJECTORY, "--channel", "POSE", "--out", d + "/pose.tum", "--lcm-url", url,
       "--count", std::to_string(want.size()), "--idle-timeout", "60"},
      d + "/recorder.txt");
  ChildProcess tracker({HS_TRACKER, "--config", d + "/node.yaml", "--calib", sim, "--lcm-url", url},
                       d + "/tracker.txt");
  ASSERT_TRUE(
      wait_for([&] { return recorder.output().find("recording") != std::string::npos; }, 20))
      << recorder.output();
  ASSERT_TRUE(wait_for([&] { return tracker.output().find("listening") != std::string::npos; }, 20))
      << tracker.output();

  ChildProcess player({"lcm-logplayer", "-l", url, log}, d + "/player.txt");
  ASSERT_TRUE(player.started());
  while (recorder.running()) lcm.handleTimeout(100);
  EXPECT_EQ(player.wait(), 0) << player.output();
  ASSERT_EQ(recorder.wait(), 0) << recorder.output();
  tracker.signal(SIGINT);
  EXPECT_EQ(tracker.wait(), 0) << tracker.output();
  while (lcm.handleTimeout(200) > 0) {
  }
  std::printf("%s", tracker.output().c_str());

  const std::vector<TumPose> got = read_tum(d + "/pose.tum");
  ASSERT_EQ(got.size(), want.size()) << recorder.output();
  double sum_sq = 0.0, max_d = 0.0;
  for (size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(got[i].t, want[i].t) << "pose " << i;
    const double e = (got[i].p - want[i].p).norm();
    sum_sq += e * e;
    max_d = std::max(max_d, e);
  }
  const double rms = std::sqrt(sum_sq / static_cast<double>(got.size()));
  EXPECT_LT(rms, 0.01);
  EXPECT_EQ(heard.dropped, 0);

  // POSE_IMU kept the IMU rate (200 Hz in room_mav) while frames were being tracked.
  ASSERT_GT(heard.pose_imu_t_ns.size(), 100u);
  const double span_s = ns_to_s(heard.pose_imu_t_ns.back() - heard.pose_imu_t_ns.front());
  const double rate_hz = static_cast<double>(heard.pose_imu_t_ns.size() - 1) / span_s;
  EXPECT_GT(rate_hz, 190.0);
  // For the record, not asserted (wall time): the longest wait between POSE_IMU arrivals.
  double max_gap_ms = 0.0;
  for (size_t i = 1; i < heard.pose_imu_arrival.size(); ++i)
    max_gap_ms = std::max(max_gap_ms, std::chrono::duration<double, std::milli>(
                                          heard.pose_imu_arrival[i] - heard.pose_imu_arrival[i - 1])
                                          .count());
  std::printf(
      "%zu POSE (hs-run %zu): position difference RMS %.3g m, max %.3g m; %lld TRACKER_STATUS, "
      "%zu POSE_IMU at %.1f Hz of sensor time, longest gap between arrivals %.1f ms; most frames "
      "queued (heartbeats): %d\n",
      got.size(), want.size(), rms, max_d, static_cast<long long>(heard.statuses),
      heard.pose_imu_t_ns.size(), rate_hz, max_gap_ms, heard.max_frame_queue);
}

TEST(TrackerProcess, ReplayAtSensorRateMatchesTheOfflineRun) {
  expect_replay_matches_offline_run({{}, "", "10"});
}

// A mono rig (issue 10) from the config: cam1 is on the log but unused, the start is the
// two-view one (room_mav moves after 2 s still; tracking from about 10 s).
TEST(TrackerProcess, MonoRigReplayMatchesTheOfflineRun) {
  expect_replay_matches_offline_run({{"--mono"}, "tracker:\n  rig: mono\n", "18"});
}

}  // namespace
}  // namespace hs
