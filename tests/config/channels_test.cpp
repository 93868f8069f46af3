#include "common/config/channels.h"

#include <gtest/gtest.h>

#include "tests/config/config_test_util.h"

namespace hs {
namespace {

using test::expect_input_error;
using test::TempYaml;

TEST(Channels, DefaultsEqualLogicalNames) {
  const ChannelNames c;
  EXPECT_EQ(c.cam_stereo, "CAM_STEREO");
  EXPECT_EQ(c.pose_imu, "POSE_IMU");
  EXPECT_EQ(c.ground_truth, "GROUND_TRUTH");
}

TEST(Channels, OverrideSomeKeepOthers) {
  TempYaml f("channels:\n  CAM_STEREO: RIG2_STEREO\n  GROUND_TRUTH: VICON\n");
  const ChannelNames c = load_channel_names(f.path());
  EXPECT_EQ(c.cam_stereo, "RIG2_STEREO");
  EXPECT_EQ(c.ground_truth, "VICON");
  EXPECT_EQ(c.imu, ChannelNames().imu);
  EXPECT_EQ(c.heartbeat, ChannelNames().heartbeat);
}

TEST(Channels, ShippedFileMatchesDefaults) {
  const ChannelNames c = load_channel_names(HS_SOURCE_DIR "/config/channels.yaml");
  const ChannelNames d;
  EXPECT_EQ(c.cam_stereo, d.cam_stereo);
  EXPECT_EQ(c.imu, d.imu);
  EXPECT_EQ(c.trigger, d.trigger);
  EXPECT_EQ(c.pose, d.pose);
  EXPECT_EQ(c.pose_imu, d.pose_imu);
  EXPECT_EQ(c.tracker_status, d.tracker_status);
  EXPECT_EQ(c.keyframe, d.keyframe);
  EXPECT_EQ(c.map_update, d.map_update);
  EXPECT_EQ(c.map_command, d.map_command);
  EXPECT_EQ(c.heartbeat, d.heartbeat);
  EXPECT_EQ(c.ground_truth, d.ground_truth);
}

TEST(Channels, UnknownChannelKeySuggestsClosest) {
  TempYaml f("channels:\n  IMU: IMU\n  GROUND_TRUHT: GT\n");
  expect_input_error([&] { load_channel_names(f.path()); },
                     {f.path() + ":3:", "channels.GROUND_TRUHT", "did you mean 'GROUND_TRUTH'"});
}

TEST(Channels, UnknownTopLevelKey) {
  TempYaml f("chanels:\n  IMU: X\n");
  expect_input_error([&] { load_channel_names(f.path()); },
                     {f.path() + ":1:", "did you mean 'channels'"});
}

TEST(Channels, WrongTypeAndBadNames) {
  {
    TempYaml f("channels:\n  IMU: [a]\n");
    expect_input_error([&] { load_channel_names(f.path()); },
                       {f.path() + ":2:", "'channels.IMU': expected a string"});
  }
  {
    TempYaml f("channels:\n  IMU: \"two words\"\n");
    expect_input_error([&] { load_channel_names(f.path()); }, {f.path() + ":2:", "whitespace"});
  }
  {
    TempYaml f("channels:\n  IMU: SAME\n  POSE: SAME\n");
    expect_input_error([&] { load_channel_names(f.path()); },
                       {f.path() + ":", "channel 'SAME' is also used for IMU"});
  }
}

TEST(Channels, MissingFile) {
  expect_input_error([] { load_channel_names("/nonexistent/channels.yaml"); },
                     {"/nonexistent/channels.yaml", "cannot open"});
}

}  // namespace
}  // namespace hs
