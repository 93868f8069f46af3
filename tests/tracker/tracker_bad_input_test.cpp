// Bad input to the tracker: each case gets a clear message and a counter, loses nothing else,
// and tracking goes on (issue 5, "Bad input").
#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "tests/tracker/sim_tracker_fixture.h"

namespace hs {
namespace {

using TrackerBadInput = test::SimTrackerTest;

TEST_F(TrackerBadInput, DuplicateAndOutOfOrderFramesAreDroppedAndCounted) {
  ASSERT_EQ(track_range(0, 30).state, TrackState::kTracking);
  const FrameResult dup = tracker_->track(frame(29));
  EXPECT_FALSE(dup.accepted);
  EXPECT_NE(dup.message.find("duplicate frame timestamp"), std::string::npos) << dup.message;
  const FrameResult old = tracker_->track(frame(20));
  EXPECT_FALSE(old.accepted);
  EXPECT_NE(old.message.find("out-of-order"), std::string::npos) << old.message;
  EXPECT_EQ(tracker_->counters().rejected_out_of_order, 2);
  EXPECT_EQ(track_range(30, 35).state, TrackState::kTracking);
}

TEST_F(TrackerBadInput, WrongImageSizeOrEncodingIsDroppedAndCounted) {
  ASSERT_EQ(track_range(0, 25).state, TrackState::kTracking);
  StereoFrame small = frame(25);
  small.cam0 = cv::Mat(240, 376, CV_8UC1, cv::Scalar(100));
  feed_imu(small.t_ns);
  const FrameResult a = tracker_->track(small);
  EXPECT_FALSE(a.accepted);
  EXPECT_NE(a.message.find("expected 752x480 mono8"), std::string::npos) << a.message;
  StereoFrame colour = frame(26);
  cv::cvtColor(colour.cam0, colour.cam0, cv::COLOR_GRAY2BGR);
  feed_imu(colour.t_ns);
  const FrameResult b = tracker_->track(colour);
  EXPECT_FALSE(b.accepted);
  EXPECT_NE(b.message.find("not mono8"), std::string::npos) << b.message;
  EXPECT_EQ(tracker_->counters().rejected_bad_image, 2);
  EXPECT_EQ(track_range(27, 32).state, TrackState::kTracking);
}

TEST_F(TrackerBadInput, MissingRightImageIsTrackedWithTheLeftCamera) {
  ASSERT_EQ(track_range(0, 25).state, TrackState::kTracking);
  StereoFrame left_only = frame(25);
  left_only.cam1 = cv::Mat();
  feed_imu(left_only.t_ns);
  const FrameResult r = tracker_->track(left_only);
  EXPECT_TRUE(r.accepted);
  EXPECT_EQ(r.state, TrackState::kTracking);
  EXPECT_NE(r.message.find("cam1 image missing"), std::string::npos) << r.message;
  EXPECT_EQ(tracker_->counters().missing_right_image, 1);
}

TEST_F(TrackerBadInput, CorruptImuSamplesAreRejectedAndCounted) {
  ASSERT_EQ(track_range(0, 25).state, TrackState::kTracking);
  const int64_t t = frame(25).t_ns;
  ImuSample nan;
  nan.t_ns = t - 1000;
  nan.gyro.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(tracker_->add_imu(nan), ImuReject::kNonFinite);
  ImuSample huge;
  huge.t_ns = t - 500;
  huge.accel = Eigen::Vector3d(0, 0, 1e4);
  EXPECT_EQ(tracker_->add_imu(huge), ImuReject::kOutOfRange);
  ImuSample past;
  past.t_ns = frame(10).t_ns;
  EXPECT_EQ(tracker_->add_imu(past), ImuReject::kOutOfOrder);
  EXPECT_EQ(tracker_->imu_counters().non_finite, 1);
  EXPECT_EQ(tracker_->imu_counters().out_of_range, 1);
  EXPECT_EQ(tracker_->imu_counters().out_of_order, 1);
  EXPECT_EQ(track_range(25, 35).state, TrackState::kTracking);
}

TEST_F(TrackerBadInput, ImuGapIsBridgedOnVisionAlone) {
  ASSERT_EQ(track_range(0, 30).state, TrackState::kTracking);
  // 0.3 s without IMU: frames 30..35 see the IMU behind them, then the gap inside the window.
  const int64_t gap_from = frame(30).t_ns - 10'000'000, gap_to = frame(36).t_ns;
  for (size_t i = 30; i < 45; ++i) {
    const StereoFrame f = frame(i);
    feed_imu(f.t_ns, gap_from, gap_to);
    const FrameResult r = tracker_->track(f);
    ASSERT_TRUE(r.accepted) << r.message;
    EXPECT_EQ(r.state, TrackState::kTracking) << "frame " << i << ": " << r.message;
  }
  EXPECT_GE(tracker_->counters().frames_without_imu, 6);
  EXPECT_EQ(tracker_->counters().lost_frames, 0);
}

TEST_F(TrackerBadInput, FramesTheImuDoesNotReachAreDroppedWhileInitialising) {
  // IMU only for the first 0.5 s: the frames after that cannot get a gravity direction.
  feed_imu(gen_.scenario().start_time_ns + 500'000'000);
  FrameResult r;
  for (size_t i = 15; i < 20; ++i) r = tracker_->track(frame(i));
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.message.find("behind the camera"), std::string::npos) << r.message;
  EXPECT_EQ(tracker_->counters().rejected_clock_offset, 5);
  EXPECT_EQ(tracker_->state(), TrackState::kInitialising);
}

}  // namespace
}  // namespace hs
