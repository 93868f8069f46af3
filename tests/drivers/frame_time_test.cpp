#include "drivers/camera/frame_time.h"

#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <stdexcept>

namespace hs {
namespace {

constexpr int64_t kMs = 1'000'000;

TEST(FrameTime, MidExposureFromStartOfExposureOrEndOfFrame) {
  const uint32_t mono = V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
  EXPECT_EQ(mid_exposure_ns({1000 * kMs, mono | V4L2_BUF_FLAG_TSTAMP_SRC_SOE}, 4 * kMs, 10 * kMs),
            1002 * kMs);
  EXPECT_EQ(mid_exposure_ns({1000 * kMs, mono | V4L2_BUF_FLAG_TSTAMP_SRC_EOF}, 4 * kMs, 10 * kMs),
            988 * kMs);  // end of frame - readout - half the exposure
  EXPECT_EQ(mid_exposure_from_trigger_ns(500 * kMs, 6 * kMs), 503 * kMs);
}

TEST(FrameTime, OtherClocksAreRefused) {
  try {
    mid_exposure_ns({1000, V4L2_BUF_FLAG_TIMESTAMP_COPY}, 0, 0);
    ADD_FAILURE();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("not CLOCK_MONOTONIC (copied from output"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(mid_exposure_ns({1000, V4L2_BUF_FLAG_TIMESTAMP_UNKNOWN}, 0, 0), std::runtime_error);
  EXPECT_EQ(
      describe_timestamp_flags(V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_SOE),
      "monotonic, start of exposure");
}

}  // namespace
}  // namespace hs
