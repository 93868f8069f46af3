// TrackerNode over in-process LCM (memq://): real messages in, real messages out.
#include "tracker/node/tracker_node.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <set>

#include "common/lcm/convert.h"
#include "common/lcm/decode.h"
#include "hsslam/heartbeat_t.hpp"
#include "tests/config/config_test_util.h"
#include "tests/lcm/lcm_test_util.h"
#include "tests/tracker/node/node_test_util.h"

namespace hs {
namespace {

using ::testing::HasSubstr;

// Every message the node publishes, decoded.
struct Outputs {
  std::vector<hsslam::odometry_t> poses, pose_imu;
  std::vector<hsslam::tracker_status_t> statuses;
  std::vector<hsslam::keyframe_t> keyframes;
  std::vector<hsslam::heartbeat_t> heartbeats;
};

using test::collect;

int64_t counter(const hsslam::tracker_status_t& s, const std::string& name) {
  for (int i = 0; i < s.num_counters; ++i)
    if (s.counter_names[i] == name) return s.counter_values[i];
  ADD_FAILURE() << "no counter " << name;
  return -1;
}

class TrackerNodeTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { seq_ = new test::SimSequence(test::make_sim_sequence(3.0)); }
  static void TearDownTestSuite() {
    delete seq_;
    seq_ = nullptr;
  }

  void SetUp() override {
    ASSERT_TRUE(lcm_.good());
    options_ = seq_->options;
    options_.node.heartbeat_period_ns = 50'000'000;
    const ChannelNames& ch = options_.channels;
    lcm_.subscribeFunction(ch.pose, &collect<hsslam::odometry_t>, &out_.poses);
    lcm_.subscribeFunction(ch.pose_imu, &collect<hsslam::odometry_t>, &out_.pose_imu);
    lcm_.subscribeFunction(ch.tracker_status, &collect<hsslam::tracker_status_t>, &out_.statuses);
    lcm_.subscribeFunction(ch.keyframe, &collect<hsslam::keyframe_t>, &out_.keyframes);
    lcm_.subscribeFunction(ch.heartbeat, &collect<hsslam::heartbeat_t>, &out_.heartbeats);
  }

  // Handles messages until none has come for 10 ms and `done()` holds (or 60 s passed).
  template <class Done>
  void pump(TrackerNode& node, Done&& done) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (std::chrono::steady_clock::now() < deadline) {
      const int handled = lcm_.handleTimeout(10);
      ASSERT_GE(handled, 0);
      node.poll();
      if (handled == 0 && done()) return;
    }
    FAIL() << "timed out waiting for the node";
  }

  // Sends the sequence, one message at a time, waiting for each frame's TRACKER_STATUS (so the
  // queue never overflows); `after_frame(k)` may send more after frame k's status.
  template <class AfterFrame>
  void replay_in_lockstep(TrackerNode& node, AfterFrame&& after_frame) {
    size_t frames = 0;
    for (const test::WireMessage& m : seq_->messages) {
      lcm_.publish(m.channel, m.bytes.data(), static_cast<unsigned>(m.bytes.size()));
      frames += m.is_frame;
      pump(node, [&] { return out_.statuses.size() == frames; });
      if (m.is_frame) after_frame(frames - 1);
    }
  }

  // POSE must be the library's result on the same input, frame by frame.
  void expect_poses_match_library() {
    std::vector<const FrameResult*> with_state;
    for (const FrameResult& r : seq_->reference)
      if (r.accepted && r.state != TrackState::kInitialising) with_state.push_back(&r);
    ASSERT_GT(with_state.size(), seq_->reference.size() / 2) << "the library barely tracked";
    ASSERT_EQ(out_.poses.size(), with_state.size());
    for (size_t i = 0; i < with_state.size(); ++i) {
      const hsslam::odometry_t& p = out_.poses[i];
      const FrameResult& r = *with_state[i];
      EXPECT_EQ(p.t_ns, r.t_ns);
      EXPECT_EQ(p.state, static_cast<int8_t>(r.state));
      EXPECT_EQ(p.map_id, r.map_id);
      EXPECT_FLOAT_EQ(p.quality, r.quality);
      for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(p.p_w_b[k], r.nav.p_w_b[k]);
      EXPECT_DOUBLE_EQ(p.covariance[6 * 4 + 4], r.pose_covariance(4, 4));
    }
  }

  static test::SimSequence* seq_;
  lcm::LCM lcm_{"memq://"};
  TrackerOptions options_;
  Outputs out_;
};

test::SimSequence* TrackerNodeTest::seq_ = nullptr;

TEST_F(TrackerNodeTest, PublishesWhatTheLibraryComputesAndPoseImuAtTheImuRate) {
  TrackerNode node(lcm_, options_);
  node.start();
  replay_in_lockstep(node, [](size_t) {});
  node.stop();
  pump(node, [] { return true; });

  ASSERT_EQ(out_.statuses.size(), seq_->reference.size());
  expect_poses_match_library();
  for (size_t i = 0; i < out_.statuses.size(); ++i) {
    EXPECT_EQ(out_.statuses[i].seq, seq_->reference[i].seq);
    EXPECT_EQ(out_.statuses[i].state, static_cast<int8_t>(seq_->reference[i].state));
    EXPECT_EQ(out_.statuses[i].num_stages, static_cast<int32_t>(out_.statuses[i].stage_ms.size()));
    // The features, as the library found them.
    const hsslam::tracker_status_t& st = out_.statuses[i];
    const FrameResult& ref = seq_->reference[i];
    ASSERT_EQ(st.num_features, static_cast<int32_t>(ref.features.size()));
    for (size_t k = 0; k < ref.features.size(); ++k) {
      EXPECT_EQ(st.feature_u[k], ref.features[k].uv.x());
      EXPECT_EQ(st.feature_v[k], ref.features[k].uv.y());
      EXPECT_EQ(st.feature_source[k], static_cast<int8_t>(ref.features[k].source));
    }
  }
  const hsslam::tracker_status_t& last = out_.statuses.back();
  EXPECT_EQ(counter(last, "frames"), static_cast<int64_t>(seq_->reference.size()));
  EXPECT_EQ(counter(last, "imu_accepted"), static_cast<int64_t>(seq_->imu.size()));
  EXPECT_EQ(counter(last, "frames_dropped_queue_full"), 0);

  // POSE_IMU: one per IMU sample after the first tracked frame (each propagated from the latest
  // frame state), so every frame interval holds the IMU rate's worth.
  const int64_t t_first = out_.poses.front().t_ns;
  std::vector<int64_t> want, got;
  for (const ImuSample& s : seq_->imu)
    if (s.t_ns > t_first) want.push_back(s.t_ns);
  for (const hsslam::odometry_t& p : out_.pose_imu) got.push_back(p.t_ns);
  EXPECT_EQ(got, want);
  // Propagated to a frame's time, it lands close to that frame's tracked pose.
  std::map<int64_t, const hsslam::odometry_t*> by_time;
  for (const hsslam::odometry_t& p : out_.pose_imu) by_time[p.t_ns] = &p;
  int compared = 0;
  for (const hsslam::odometry_t& pose : out_.poses) {
    const auto it = by_time.find(pose.t_ns);
    if (it == by_time.end()) continue;
    ++compared;
    const Eigen::Vector3d d = Eigen::Map<const Eigen::Vector3d>(it->second->p_w_b) -
                              Eigen::Map<const Eigen::Vector3d>(pose.p_w_b);
    EXPECT_LT(d.norm(), 0.02) << "at t_ns " << pose.t_ns;
  }
  EXPECT_EQ(compared, static_cast<int>(out_.poses.size()) - 1);
  const double span_s = ns_to_s(out_.pose_imu.back().t_ns - out_.pose_imu.front().t_ns);
  std::printf("POSE %zu, POSE_IMU %zu (%.1f Hz over %.2f s of sensor time)\n", out_.poses.size(),
              out_.pose_imu.size(), static_cast<double>(out_.pose_imu.size() - 1) / span_s, span_s);

  // KEYFRAME: one per keyframe status, self-consistent.
  size_t keyframe_statuses = 0;
  for (const auto& s : out_.statuses) keyframe_statuses += s.is_keyframe;
  ASSERT_GE(out_.keyframes.size(), 1u);
  EXPECT_EQ(out_.keyframes.size(), keyframe_statuses);
  for (const hsslam::keyframe_t& kf : out_.keyframes) {
    EXPECT_EQ(kf.t_ns, kf.pose.t_ns);
    ASSERT_EQ(kf.num_keypoints, static_cast<int32_t>(kf.keypoints.size()));
    ASSERT_EQ(kf.descriptors.size(), kf.keypoints.size());
    EXPECT_EQ(kf.num_points, static_cast<int32_t>(kf.points.size()));
    std::set<int64_t> ids;
    for (const hsslam::map_point_t& p : kf.points) EXPECT_TRUE(ids.insert(p.id).second);
    std::set<int64_t> observed;
    for (const hsslam::keypoint_t& k : kf.keypoints)
      if (k.map_point_id >= 0) observed.insert(k.map_point_id);
    EXPECT_EQ(observed, ids);
    EXPECT_GT(kf.num_points, 30);
    EXPECT_EQ(kf.num_imu, static_cast<int32_t>(kf.imu.size()));
  }
  EXPECT_EQ(out_.keyframes.front().prev_keyframe_id, -1);
  for (size_t i = 1; i < out_.keyframes.size(); ++i) {  // chained, with the IMU in between
    const hsslam::keyframe_t &prev = out_.keyframes[i - 1], &kf = out_.keyframes[i];
    EXPECT_EQ(kf.prev_keyframe_id, prev.pose.id);
    ASSERT_GT(kf.num_imu, 0);
    EXPECT_GE(kf.imu.front().t_ns, prev.t_ns - 5'000'000);
    EXPECT_LE(kf.imu.back().t_ns, kf.t_ns + 5'000'000);
  }

  // HEARTBEAT: STARTING first, STOPPING last, with queue depths and the counters.
  ASSERT_GE(out_.heartbeats.size(), 2u);
  EXPECT_EQ(out_.heartbeats.front().state, hsslam::heartbeat_t::STARTING);
  EXPECT_EQ(out_.heartbeats.back().state, hsslam::heartbeat_t::STOPPING);
  EXPECT_EQ(out_.heartbeats.back().process, "hs-tracker");
  EXPECT_EQ(out_.heartbeats.back().queue_names,
            (std::vector<std::string>{"frames", "imu_samples", "map_updates"}));
  EXPECT_EQ(out_.heartbeats.back().queue_depths, (std::vector<int32_t>{0, 0, 0}));
  EXPECT_EQ(out_.heartbeats.back().num_counters, last.num_counters);
}

TEST_F(TrackerNodeTest, MalformedMessagesAreCountedAndTrackingContinues) {
  const ChannelNames& ch = options_.channels;
  const auto first = [&](bool frame) {
    return std::find_if(seq_->messages.begin(), seq_->messages.end(),
                        [&](const test::WireMessage& m) { return m.is_frame == frame; })
        ->bytes;
  };
  const std::vector<uint8_t> frame_bytes = first(true);
  hsslam::stereo_frame_t bad_stride =
      decode_message<hsslam::stereo_frame_t>(frame_bytes.data(), frame_bytes.size(), "test");
  bad_stride.images[1].stride = bad_stride.images[1].width - 1;
  hsslam::imu_batch_t backwards = imu_batch_to_msg({seq_->imu[1], seq_->imu[0]}, 0);
  backwards.t_ns = seq_->imu[0].t_ns;
  std::vector<uint8_t> truncated = first(false);
  truncated.resize(truncated.size() - 5);
  const std::vector<test::WireMessage> bad = {{ch.cam_stereo, {1, 2, 3}, true},
                                              {ch.cam_stereo, test::encode(bad_stride), true},
                                              {ch.imu, truncated, false},
                                              {ch.imu, test::encode(backwards), false},
                                              {ch.imu, test::encode(hsslam::odometry_t{}), false}};
  const size_t inject_after = seq_->reference.size() / 2;

  TrackerNode node(lcm_, options_);
  node.start();
  replay_in_lockstep(node, [&](size_t k) {
    if (k != inject_after) return;
    for (const test::WireMessage& m : bad)
      lcm_.publish(m.channel, m.bytes.data(), static_cast<unsigned>(m.bytes.size()));
    pump(node, [] { return true; });
  });
  node.stop();

  expect_poses_match_library();
  ASSERT_EQ(out_.statuses.size(), seq_->reference.size());
  EXPECT_THAT(out_.statuses[inject_after + 1].message,
              HasSubstr("5 bad inputs ignored, last: " + ch.imu + ": message is not a"));
  EXPECT_THAT(out_.statuses[inject_after + 2].message, ::testing::Not(HasSubstr("bad input")));
  const hsslam::tracker_status_t& last = out_.statuses.back();
  EXPECT_EQ(counter(last, "bad_frame_messages"), 2);
  EXPECT_EQ(counter(last, "bad_imu_messages"), 3);
  EXPECT_EQ(counter(last, "frames_received"), static_cast<int64_t>(seq_->reference.size()));
  const NodeStats stats = node.stats();
  EXPECT_EQ(stats.bad_frame_messages, 2);
  EXPECT_EQ(stats.bad_imu_messages, 3);
}

TEST_F(TrackerNodeTest, MapUpdatesAreAppliedBetweenFramesAndTheirSequenceChecked) {
  const ChannelNames& ch = options_.channels;
  const size_t inject_after = seq_->reference.size() / 2;
  // A correction that leaves the newest keyframe the node sent where it was.
  const auto update = [&](int64_t seq) {
    const hsslam::keyframe_t& kf = out_.keyframes.back();
    MapCorrection c;
    c.seq = seq;
    c.map_id = kf.map_id;
    c.t_ns = kf.t_ns;
    c.keyframes.push_back({kf.pose.id, keyframe_pose_from_msg(kf.pose, "test")});
    return test::encode(map_update_to_msg(c));
  };
  TrackerNode node(lcm_, options_);
  node.start();
  replay_in_lockstep(node, [&](size_t k) {
    if (k != inject_after) return;
    ASSERT_FALSE(out_.keyframes.empty());
    hsslam::map_update_t loop = map_update_to_msg(MapCorrection{});
    loop.kind = hsslam::map_update_t::LOOP;
    // 0 applied; 0 again stale; 3 applied after 2 lost; a LOOP refused; 0 a restarted mapper.
    for (const std::vector<uint8_t>& bytes :
         {update(0), update(0), update(3), test::encode(loop), update(0)})
      lcm_.publish(ch.map_update, bytes.data(), static_cast<unsigned>(bytes.size()));
    pump(node, [] { return true; });
  });
  node.stop();

  const hsslam::tracker_status_t& last = out_.statuses.back();
  EXPECT_EQ(last.state, hsslam::odometry_t::TRACKING);
  EXPECT_EQ(counter(last, "map_updates_received"), 4);
  EXPECT_EQ(counter(last, "map_updates_stale"), 1);
  EXPECT_EQ(counter(last, "map_updates_lost"), 2);
  EXPECT_EQ(counter(last, "mapper_restarts"), 1);
  EXPECT_EQ(counter(last, "bad_map_update_messages"), 1);
  EXPECT_EQ(counter(last, "corrections_applied"), 3);
  EXPECT_EQ(counter(last, "correction_jumps"), 0);
  EXPECT_THAT(out_.statuses[inject_after + 1].message, HasSubstr("kind LOOP is not supported"));
}

TEST_F(TrackerNodeTest, FullQueueDropsTheOldestFrameButNoImu) {
  options_.node.frame_queue_size = 2;
  TrackerNode node(lcm_, options_);  // not started: everything waits in the queue
  int frames = 0;
  int64_t imu_samples = 0;
  for (const test::WireMessage& m : seq_->messages) {
    lcm_.publish(m.channel, m.bytes.data(), static_cast<unsigned>(m.bytes.size()));
    pump(node, [] { return true; });
    if (!m.is_frame)
      imu_samples += decode_message<hsslam::imu_batch_t>(m.bytes.data(), m.bytes.size(), m.channel)
                         .num_samples;
    if (m.is_frame && ++frames == 5) break;
  }
  EXPECT_EQ(node.stats().frames_received, 5);
  EXPECT_EQ(node.stats().frames_dropped, 3);
  node.start();
  pump(node, [&] { return out_.statuses.size() == 2; });
  node.stop();

  ASSERT_EQ(out_.statuses.size(), 2u);
  EXPECT_EQ(out_.statuses[0].seq, 3);  // the two newest frames
  EXPECT_EQ(out_.statuses[1].seq, 4);
  EXPECT_THAT(out_.statuses[0].message,
              HasSubstr("3 oldest frames dropped: tracker queue full (total 3)"));
  EXPECT_EQ(counter(out_.statuses[1], "frames_dropped_queue_full"), 3);
  // The IMU samples queued around the dropped frames all reached the tracker.
  EXPECT_EQ(counter(out_.statuses[1], "imu_accepted"), imu_samples);
  EXPECT_GT(imu_samples, 0);
}

TEST(NodeOptions, ReadFromTheNodeSectionOfTheTrackerConfig) {
  const test::TempYaml good(
      "node:\n  frame_queue_size: 5\n  pose_imu_decimation: 4\n  heartbeat_period_s: 0.5\n");
  const NodeOptions o = load_tracker_options(good.path()).node;
  EXPECT_EQ(o.frame_queue_size, 5);
  EXPECT_EQ(o.pose_imu_decimation, 4);
  EXPECT_EQ(o.heartbeat_period_ns, 500'000'000);
  const test::TempYaml bad("node:\n  frame_queue_size: 0\n");
  test::expect_input_error([&] { load_tracker_options(bad.path()); },
                           {bad.path() + ":2", "frame_queue_size"});
}

}  // namespace
}  // namespace hs
