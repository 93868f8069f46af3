#include "drivers/camera/camera_options.h"

#include <gtest/gtest.h>

#include "tests/config/config_test_util.h"

namespace hs {
namespace {

TEST(CameraOptions, ShippedConfigLoads) {
  const CameraOptions o = load_camera_options(HS_SOURCE_DIR "/config/camera.yaml");
  ASSERT_EQ(o.devices.size(), 2u);
  EXPECT_EQ(o.format.width, 752);
  EXPECT_EQ(o.format.format, PixelFormat::kGrey);
  EXPECT_EQ(o.mode, TriggerMode::kFreeRunning);
  EXPECT_EQ(o.max_stereo_skew_ns, 2'000'000);
  EXPECT_EQ(o.trigger.max_latency_ns, 40'000'000);
  EXPECT_TRUE(o.format.exposure_control);
}

TEST(CameraOptions, ExposureSetByOtherMeans) {
  test::TempYaml yaml(
      "camera:\n  mode: external-trigger\n  exposure_s: 0.004\n  exposure_control: false\n");
  const CameraOptions o = load_camera_options(yaml.path());
  EXPECT_EQ(o.mode, TriggerMode::kExternal);
  EXPECT_EQ(o.format.exposure_ns, 4'000'000);
  EXPECT_FALSE(o.format.exposure_control);
}

TEST(CameraOptions, BadValuesAreClearErrors) {
  test::TempYaml format("camera:\n  format: MJPG\n");
  test::expect_input_error([&] { load_camera_options(format.path()); },
                           {format.path() + ":2", "'MJPG' not supported"});
  test::TempYaml sbs("camera:\n  side_by_side: true\n");
  test::expect_input_error([&] { load_camera_options(sbs.path()); }, {"exactly one device"});
  test::TempYaml trig("camera:\n  mode: external-trigger\n");
  test::expect_input_error([&] { load_camera_options(trig.path()); },
                           {"external-trigger mode needs the exposure"});
  test::TempYaml three("camera:\n  devices: [a, b, c]\n");
  test::expect_input_error([&] { load_camera_options(three.path()); }, {"one or two devices"});
}

}  // namespace
}  // namespace hs
