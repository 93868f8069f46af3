#include "common/dataset/euroc_stream.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "tests/dataset/dataset_test_util.h"

namespace hs {
namespace {

// Replays the whole stream and checks it against the reader: every item exactly once, in
// non-decreasing time, IMU before ground truth before frame at equal times.
void expect_ordered_stream(const EurocReader& r) {
  EurocStream stream(r);
  EXPECT_EQ(stream.size(), r.imu().size() + r.ground_truth().size() + r.frames().size());
  size_t imu = 0, gt = 0, frames = 0;
  int64_t prev_t = INT64_MIN;
  size_t prev_kind = 0;
  DatasetEvent e;
  while (stream.next(e)) {
    const size_t kind = e.index();  // variant order: ImuSample, NavState, StereoFrame
    const int64_t t = std::visit([](const auto& x) { return x.t_ns; }, e);
    ASSERT_GE(t, prev_t);
    if (t == prev_t) {
      EXPECT_GE(kind, prev_kind);
    }
    if (kind == 0) {
      EXPECT_EQ(std::get<ImuSample>(e).t_ns, r.imu()[imu++].t_ns);
    } else if (kind == 1) {
      EXPECT_EQ(std::get<NavState>(e).t_ns, r.ground_truth()[gt++].t_ns);
    } else {
      const StereoFrame& f = std::get<StereoFrame>(e);
      EXPECT_EQ(f.seq, static_cast<int64_t>(frames));
      EXPECT_EQ(f.t_ns, r.frames()[frames++].t_ns);
      EXPECT_EQ(f.cam0.size(), r.image_size());
      EXPECT_EQ(f.stereo(), r.stereo());
    }
    prev_t = t;
    prev_kind = kind;
  }
  EXPECT_EQ(imu, r.imu().size());
  EXPECT_EQ(gt, r.ground_truth().size());
  EXPECT_EQ(frames, r.frames().size());
  EXPECT_EQ(stream.position(), stream.size());
  EXPECT_FALSE(stream.next(e));
}

TEST(EurocStream, SampleInSensorTimeOrder) {
  const EurocReader r(test::kSampleRoot);
  // The sample has IMU, ground truth and a frame at the very same first timestamp.
  ASSERT_EQ(r.imu()[0].t_ns, r.frames()[0].t_ns);
  ASSERT_EQ(r.ground_truth()[0].t_ns, r.frames()[0].t_ns);
  expect_ordered_stream(r);
}

TEST(EurocStream, SharedSequences) {
  bool any = false;
  for (const char* name : {"V1_01_static_stereo", "V1_01_flight_cam0"}) {
    const std::string root = test::kSharedEuroc + "/" + name;
    if (!std::filesystem::exists(root)) continue;
    any = true;
    SCOPED_TRACE(name);
    expect_ordered_stream(EurocReader(root));
  }
  if (!any) GTEST_SKIP() << test::kSharedEuroc << " absent (shared EuRoC pieces)";
}

}  // namespace
}  // namespace hs
