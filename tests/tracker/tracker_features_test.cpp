// The features a frame result carries for viewers: every tracked point with how it was found.
#include <gtest/gtest.h>

#include "tests/tracker/sim_tracker_fixture.h"

namespace hs {
namespace {

using TrackerFeatures = test::SimTrackerTest;

TEST_F(TrackerFeatures, EveryTrackedPointWithHowItWasFound) {
  const cv::Size size = frame(0).cam0.size();
  int direct_frames = 0, keyframes_with_new = 0;
  for (size_t i = 0; i < gen_.num_frames(); ++i) {
    const StereoFrame f = frame(i);
    feed_imu(f.t_ns);
    const FrameResult r = tracker_->track(f);
    ASSERT_TRUE(r.accepted) << r.message;
    if (r.state == TrackState::kInitialising || r.state == TrackState::kLost) continue;
    ASSERT_EQ(r.features.size(), static_cast<size_t>(r.tracked_points)) << "frame " << i;
    int found = 0, fresh = 0;
    for (const FrameFeature& feature : r.features) {
      EXPECT_GE(feature.uv.x(), 0.0f);
      EXPECT_GE(feature.uv.y(), 0.0f);
      EXPECT_LT(feature.uv.x(), static_cast<float>(size.width));
      EXPECT_LT(feature.uv.y(), static_cast<float>(size.height));
      if (feature.source == FeatureSource::kNew) {
        ++fresh;
        continue;
      }
      ++found;
      // Points found in this frame (before any new ones) all come from the frame's method.
      EXPECT_EQ(fresh, 0) << "new points come last";
      EXPECT_EQ(feature.source, r.method == TrackMethod::kDirect ? FeatureSource::kDirect
                                                                 : FeatureSource::kDescriptor);
    }
    if (!r.is_keyframe) {
      EXPECT_EQ(fresh, 0) << "only keyframes create points";
    }
    keyframes_with_new += r.is_keyframe && fresh > 0;
    direct_frames += r.method == TrackMethod::kDirect && found > 0;
  }
  EXPECT_GT(direct_frames, 10);
  EXPECT_GE(keyframes_with_new, 1);
}

}  // namespace
}  // namespace hs
