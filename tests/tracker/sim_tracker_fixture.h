#pragma once
// A tracker fed frame by frame from a short simulated room_mav flight (2.3 s: 1 s of IMU
// history, tracking at rest, the first motion), for tests that poke it between frames.
#include <gtest/gtest.h>

#include <memory>

#include "common/sim/dataset_gen.h"
#include "common/sim/scenario.h"
#include "tracker/tracker.h"

namespace hs::test {

class SimTrackerTest : public ::testing::Test {
 protected:
  SimTrackerTest() : gen_(scenario()) {
    options_.calib = gen_.scenario().camera.calib;
    tracker_ = std::make_unique<Tracker>(options_);
  }

  static sim::Scenario scenario() {
    sim::Scenario s = sim::load_scenario(HS_SOURCE_DIR "/config/sim/room_mav.yaml");
    s.duration_s = 2.3;  // 1 s of IMU history, then tracking at rest and the first motion
    return s;
  }

  StereoFrame frame(size_t i) {
    const sim::SimStereoFrame f = gen_.frame(i);
    StereoFrame out;
    out.t_ns = f.t_ns;
    out.seq = static_cast<int64_t>(i);
    out.cam0 = f.cam0;
    out.cam1 = f.cam1;
    return out;
  }

  // IMU samples up to and including t_ns, except those in [skip_from_ns, skip_to_ns).
  void feed_imu(int64_t t_ns, int64_t skip_from_ns = 0, int64_t skip_to_ns = 0) {
    const auto& samples = gen_.imu().samples;
    for (; next_imu_ < samples.size() && samples[next_imu_].t_ns <= t_ns; ++next_imu_) {
      const ImuSample& s = samples[next_imu_];
      if (s.t_ns >= skip_from_ns && s.t_ns < skip_to_ns) continue;
      tracker_->add_imu(s);
    }
  }

  // Tracks frames [from, to) with their IMU; returns the last result.
  FrameResult track_range(size_t from, size_t to) {
    FrameResult r;
    for (size_t i = from; i < to; ++i) {
      const StereoFrame f = frame(i);
      feed_imu(f.t_ns);
      r = tracker_->track(f);
      EXPECT_TRUE(r.accepted) << "frame " << i << ": " << r.message;
    }
    return r;
  }

  sim::DatasetGenerator gen_;
  TrackerOptions options_;
  std::unique_ptr<Tracker> tracker_;
  size_t next_imu_ = 0;
};

}  // namespace hs::test
