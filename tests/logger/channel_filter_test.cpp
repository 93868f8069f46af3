#include "logger/channel_filter.h"

#include <gtest/gtest.h>

#include "common/core/error.h"

namespace hs {
namespace {

TEST(ChannelFilter, IncludesAndExcludesMatchWholeNames) {
  ChannelFilter f({"CAM_.*", "IMU", "POSE.*"}, {".*_IMU", "CAM_DEBUG"});
  EXPECT_TRUE(f.keep("CAM_STEREO"));
  EXPECT_TRUE(f.keep("IMU"));
  EXPECT_TRUE(f.keep("POSE"));
  EXPECT_FALSE(f.keep("POSE_IMU"));   // excluded
  EXPECT_FALSE(f.keep("CAM_DEBUG"));  // excluded
  EXPECT_FALSE(f.keep("IMU2"));       // "IMU" must match the whole name
  EXPECT_FALSE(f.keep("MY_CAM_STEREO"));
  EXPECT_FALSE(f.keep("HEARTBEAT"));
  EXPECT_TRUE(f.keep("CAM_STEREO"));  // cached answer is the same
}

TEST(ChannelFilter, ABadPatternIsNamed) {
  try {
    ChannelFilter f({"CAM_(STEREO"}, {});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("CAM_(STEREO"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hs
