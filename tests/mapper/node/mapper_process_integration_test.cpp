// hs-tracker and hs-mapper as two processes over udpm multicast on loopback, fed by stock
// lcm-logplayer (issue 6, "Runs" and "Faults"): the trajectory they publish against the
// in-process run (hs-run --with-mapper), and what a killed and restarted mapper does to POSE
// at 1x; hs-map-save asking a running mapper for its map, and a mapper started from it.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/lcm/decode.h"
#include "common/lcm/lcm_connection.h"
#include "hsslam/odometry_t.hpp"
#include "hsslam/tracker_status_t.hpp"
#include "mapper/map_file.h"
#include "tests/common/ate_test_util.h"
#include "tests/common/child_process.h"
#include "tests/common/process_test_util.h"
#include "tests/common/sim_log_util.h"
#include "tests/dataset/dataset_test_util.h"

namespace hs {
namespace {

using test::ChildProcess;
using test::wait_for;

// POSE times and the tracker's latest counters, as heard by the test.
struct Heard {
  std::vector<int64_t> pose_t_ns;
  std::vector<std::string> counter_names;
  std::vector<int64_t> counter_values;
  int64_t counter(const std::string& name) const {
    for (size_t i = 0; i < counter_names.size(); ++i)
      if (counter_names[i] == name) return counter_values[i];
    return -1;
  }
  static void on(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Heard* self) {
    try {
      if (channel == "POSE") {
        self->pose_t_ns.push_back(
            decode_message<hsslam::odometry_t>(rbuf->data, rbuf->data_size, channel).t_ns);
      } else {
        const auto s =
            decode_message<hsslam::tracker_status_t>(rbuf->data, rbuf->data_size, channel);
        self->counter_names = s.counter_names;
        self->counter_values = s.counter_values;
      }
    } catch (const std::exception& e) {
      ADD_FAILURE() << e.what();
    }
  }
};

double ate_rmse(const std::string& gt, const std::string& estimate, const std::string& json) {
  return test::ate_rmse(HS_EVAL, gt, estimate, json);
}

class MapperProcess : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    const std::string d = dir_->path();
    ASSERT_TRUE(test::make_sim_log(HS_SIM, HS_EUROC2LCM, d, 12));
    ChildProcess run({HS_RUN, "--dataset", d + "/sim", "--with-mapper", "--out", d + "/run"},
                     d + "/run.txt");
    ASSERT_EQ(run.wait(), 0) << run.output();
    // A roomy frame queue: CI machines may stall the tracker while other jobs run.
    std::ofstream(d + "/node.yaml") << "node:\n  frame_queue_size: 100\n";
    // hs-run's in-process mapper has no CPU budget per BA (reproducible runs); hs-mapper's is
    // 100 ms, which a slow host crosses, cutting BAs short (1.28x and 1.69x the in-process ATE
    // on a host where the BA's p95 was 130 ms). Comparing the split: the same BAs on both sides.
    std::ofstream(d + "/unbudgeted.yaml") << "local_ba:\n  time_budget_ms: 1.0e9\n";
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }

  void SetUp() override {
    ASSERT_GE(read_rmem_max(), kWantedReceiveBuffer)
        << "net.core.rmem_max too small for camera frames over udpm: run tools/setup.sh as root";
    ASSERT_TRUE(lcm_.good()) << "cannot open " << url_ << ": no multicast route? tools/setup.sh";
    lcm_.subscribeFunction("(POSE|TRACKER_STATUS)", &Heard::on, &heard_);
  }

  std::string d() const { return dir_->path(); }
  std::string gt() const { return d() + "/sim/mav0/state_groundtruth_estimate0/data.csv"; }
  std::vector<std::string> mapper_cmd() const {
    return {HS_MAPPER, "--calib", d() + "/sim", "--lcm-url", url_};
  }
  static bool listening(ChildProcess& p) {
    return wait_for([&] { return p.output().find("listening") != std::string::npos; }, 20);
  }
  // Handles LCM until `done()` (at most `seconds`).
  template <class Done>
  void pump(Done&& done, int seconds) {
    wait_for(
        [&] {
          while (lcm_.handleTimeout(10) > 0) {
          }
          return done();
        },
        seconds);
  }

  static test::TempDir* dir_;
  const std::string url_ = test::private_udpm_url(7);
  lcm::LCM lcm_{url_};
  Heard heard_;
};

test::TempDir* MapperProcess::dir_ = nullptr;

TEST_F(MapperProcess, TwoProcessesThroughLogplayerMatchTheInProcessRun) {
  const double in_process = ate_rmse(gt(), d() + "/run/trajectory.tum", d() + "/run_eval.json");
  ChildProcess recorder(
      {HS_RECORD_TRAJECTORY, "--channel", "POSE", "--out", d() + "/pose.tum", "--lcm-url", url_},
      d() + "/recorder.txt");
  ChildProcess tracker(
      {HS_TRACKER, "--config", d() + "/node.yaml", "--calib", d() + "/sim", "--lcm-url", url_},
      d() + "/tracker.txt");
  std::vector<std::string> mapper_args = mapper_cmd();
  mapper_args.insert(mapper_args.end(), {"--config", d() + "/unbudgeted.yaml"});
  ChildProcess mapper(mapper_args, d() + "/mapper.txt");
  ASSERT_TRUE(listening(tracker)) << tracker.output();
  ASSERT_TRUE(listening(mapper)) << mapper.output();
  ASSERT_TRUE(
      wait_for([&] { return recorder.output().find("recording") != std::string::npos; }, 20));
  // Eighth speed (a frame every 400 ms): the comparison is of the split, not of the host's
  // speed. Every correction then reaches the tracker before the next frame, as in process, and
  // the two trajectories are the same (measured 1.00x). A correction applied L frames
  // after its keyframe leaves those frames uncorrected: at half speed, where a slow BA makes L
  // one frame now and then, 1.03-1.11x; at quarter speed on a slow host (BA p95 130 ms), 1.10x
  // in half the runs. The 1x timing is tested below and by the backlog.
  ChildProcess player({"lcm-logplayer", "-s", "0.125", "-l", url_, d() + "/sim.lcmlog"},
                      d() + "/player.txt");
  pump([&] { return !player.running(); }, 240);
  EXPECT_EQ(player.wait(), 0) << player.output();
  pump([] { return false; }, 1);  // the last frame's POSE
  tracker.signal(SIGINT);
  mapper.signal(SIGINT);
  EXPECT_EQ(tracker.wait(), 0) << tracker.output();
  EXPECT_EQ(mapper.wait(), 0) << mapper.output();
  pump([] { return false; }, 1);
  recorder.signal(SIGINT);
  ASSERT_EQ(recorder.wait(), 0) << recorder.output();

  const double two_processes = ate_rmse(gt(), d() + "/pose.tum", d() + "/pose_eval.json");
  std::printf("ATE in process %.4f m, two processes %.4f m (%.2fx)\n%s%s", in_process,
              two_processes, two_processes / in_process, tracker.output().c_str(),
              mapper.output().c_str());
  // A CI host busy with other tests may still delay a correction by a frame: the issue allows 10%.
  EXPECT_LE(two_processes, 1.1 * in_process);
  EXPECT_GT(heard_.counter("corrections_applied"), 20);
  // Corrections may come a frame late over LCM (the keyframe's ORB, the BA, two hops: 150 ms
  // seen under load at half speed; at quarter speed on a quiet host at most 50), but not by
  // seconds.
  std::printf("corrections at most %lld ms after their keyframe\n",
              static_cast<long long>(heard_.counter("max_correction_lag_ms")));
  EXPECT_GE(heard_.counter("max_correction_lag_ms"), 0) << "reported";
  EXPECT_LT(heard_.counter("max_correction_lag_ms"), 1000);
  EXPECT_EQ(heard_.counter("map_updates_lost"), 0);
  // The mapper kept up: every keyframe mapped, the backlog stayed small.
  EXPECT_NE(mapper.output().find("(0 bad)"), std::string::npos) << mapper.output();
  const size_t at = mapper.output().find("backlog at most ");
  ASSERT_NE(at, std::string::npos);
  EXPECT_LE(std::stoi(mapper.output().substr(at + 16)), 3) << mapper.output();
}

TEST_F(MapperProcess, KilledMapperLeavesPoseGaplessAndARestartedOneResumes) {
  ChildProcess tracker(
      {HS_TRACKER, "--config", d() + "/node.yaml", "--calib", d() + "/sim", "--lcm-url", url_},
      d() + "/tracker2.txt");
  auto mapper = std::make_unique<ChildProcess>(mapper_cmd(), d() + "/mapper2.txt");
  ASSERT_TRUE(listening(tracker)) << tracker.output();
  ASSERT_TRUE(listening(*mapper)) << mapper->output();
  ChildProcess player({"lcm-logplayer", "-l", url_, d() + "/sim.lcmlog"}, d() + "/player2.txt");
  // 4 s into the flight (2 s of it moving), kill -9; 1 s later a new mapper.
  pump([&] { return heard_.pose_t_ns.size() >= 60; }, 30);
  mapper->signal(SIGKILL);
  EXPECT_EQ(mapper->wait(), 128 + SIGKILL);
  pump([] { return false; }, 1);
  const int64_t applied_before = heard_.counter("corrections_applied");
  const size_t poses_before = heard_.pose_t_ns.size();
  pump([&] { return heard_.pose_t_ns.size() >= poses_before + 20; }, 30);
  EXPECT_EQ(heard_.counter("corrections_applied"), applied_before);  // nobody corrects
  mapper = std::make_unique<ChildProcess>(mapper_cmd(), d() + "/mapper3.txt");
  ASSERT_TRUE(listening(*mapper)) << mapper->output();
  pump([&] { return !player.running(); }, 60);
  EXPECT_EQ(player.wait(), 0) << player.output();
  pump([] { return false; }, 3);
  tracker.signal(SIGINT);
  mapper->signal(SIGINT);
  EXPECT_EQ(tracker.wait(), 0) << tracker.output();
  pump([] { return false; }, 1);

  // POSE at the full frame rate throughout: no gap longer than a frame period (20 Hz).
  ASSERT_GT(heard_.pose_t_ns.size(), 200u);
  int64_t max_gap_ns = 0;
  for (size_t i = 1; i < heard_.pose_t_ns.size(); ++i)
    max_gap_ns = std::max(max_gap_ns, heard_.pose_t_ns[i] - heard_.pose_t_ns[i - 1]);
  EXPECT_LE(max_gap_ns, 51'000'000);
  // The new mapper's updates start at 0 again: taken as a restart, and corrections resume.
  EXPECT_EQ(heard_.counter("mapper_restarts"), 1);
  EXPECT_GT(heard_.counter("corrections_applied"), applied_before + 3)
      << "ignored: " << heard_.counter("corrections_ignored") << "\n"
      << mapper->output();
  EXPECT_EQ(heard_.counter("correction_jumps"), 0);
}

// Issue 7: "writes the atlas at exit or on an LCM command". A mapper mid-run writes its map when
// asked over MAP_COMMAND and says where in its heartbeat; a path it cannot write gets the reason
// and the mapper goes on; a new mapper starts from the file in localisation-only mode; a
// truncated copy is refused with the file's name.
TEST_F(MapperProcess, AMapperSavesItsMapOnRequestAndANewOneStartsFromIt) {
  ChildProcess tracker(
      {HS_TRACKER, "--config", d() + "/node.yaml", "--calib", d() + "/sim", "--lcm-url", url_},
      d() + "/tracker4.txt");
  ChildProcess mapper(mapper_cmd(), d() + "/mapper4.txt");
  ASSERT_TRUE(listening(tracker)) << tracker.output();
  ASSERT_TRUE(listening(mapper)) << mapper.output();
  ChildProcess player({"lcm-logplayer", "-l", url_, d() + "/sim.lcmlog"}, d() + "/player4.txt");
  pump([&] { return heard_.pose_t_ns.size() >= 120; }, 30);  // keyframes are being mapped

  const std::string saved = d() + "/live.hsmap";
  ChildProcess save({HS_MAP_SAVE, saved, "--lcm-url", url_, "--timeout", "30"}, d() + "/save.txt");
  EXPECT_EQ(save.wait(), 0) << save.output();
  EXPECT_NE(save.output().find("map saved to " + saved), std::string::npos) << save.output();
  const MapFile map = read_map_file(saved);
  EXPECT_GE(map.keyframes.size(), 3u);

  ChildProcess refused({HS_MAP_SAVE, "/nonexistent-dir/x.hsmap", "--lcm-url", url_},
                       d() + "/r.txt");
  EXPECT_EQ(refused.wait(), 1) << refused.output();
  EXPECT_NE(refused.output().find("failed"), std::string::npos) << refused.output();
  EXPECT_NE(refused.output().find("/nonexistent-dir/x.hsmap"), std::string::npos);
  EXPECT_TRUE(mapper.running());

  pump([&] { return !player.running(); }, 60);
  tracker.signal(SIGINT);
  mapper.signal(SIGINT);
  EXPECT_EQ(tracker.wait(), 0) << tracker.output();
  EXPECT_EQ(mapper.wait(), 0) << mapper.output();

  ChildProcess loaded({HS_MAPPER, "--calib", d() + "/sim", "--lcm-url", url_, "--load-map", saved,
                       "--localisation-only"},
                      d() + "/mapper5.txt");
  ASSERT_TRUE(listening(loaded)) << loaded.output();
  EXPECT_NE(loaded.output().find("loaded " + std::to_string(map.keyframes.size()) + " keyframes"),
            std::string::npos)
      << loaded.output();
  loaded.signal(SIGINT);
  EXPECT_EQ(loaded.wait(), 0) << loaded.output();

  std::filesystem::resize_file(saved, std::filesystem::file_size(saved) / 2);
  ChildProcess truncated(
      {HS_MAPPER, "--calib", d() + "/sim", "--lcm-url", url_, "--load-map", saved},
      d() + "/mapper6.txt");
  EXPECT_NE(truncated.wait(), 0);
  EXPECT_NE(truncated.output().find(saved), std::string::npos) << truncated.output();
  EXPECT_NE(truncated.output().find("truncated"), std::string::npos) << truncated.output();
}

}  // namespace
}  // namespace hs
