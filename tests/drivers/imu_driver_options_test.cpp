#include "drivers/imu/imu_driver_options.h"

#include <gtest/gtest.h>

#include "tests/config/config_test_util.h"

namespace hs {
namespace {

TEST(ImuDriverOptions, ShippedConfigLoads) {
  const ImuDriverOptions o = load_imu_driver_options(HS_SOURCE_DIR "/config/imu.yaml");
  EXPECT_EQ(o.backend, "xsens");
  EXPECT_EQ(o.baud, 921600);
  EXPECT_EQ(o.batch_size, 4);
  EXPECT_EQ(o.clock.window_ns, 10'000'000'000);
}

TEST(ImuDriverOptions, BadValuesAreClearErrors) {
  test::TempYaml backend("imu:\n  backend: mavlink\n");
  test::expect_input_error([&] { load_imu_driver_options(backend.path()); },
                           {backend.path() + ":2", "must be 'xsens'"});
  test::TempYaml axes("iio:\n  gyro_channels: [in_anglvel_x, in_anglvel_y]\n");
  test::expect_input_error([&] { load_imu_driver_options(axes.path()); },
                           {axes.path() + ":2", "3 scan elements"});
  test::TempYaml length("iio:\n  buffer_length: 1\n");
  test::expect_input_error([&] { load_imu_driver_options(length.path()); }, {"2 ... 65536"});
  test::TempYaml baud("imu:\n  baud: 1000\n");
  test::expect_input_error([&] { load_imu_driver_options(baud.path()); },
                           {baud.path() + ":2", "unsupported baud rate 1000"});
  test::TempYaml batch("imu:\n  batch_size: 0\n");
  test::expect_input_error([&] { load_imu_driver_options(batch.path()); }, {"1 ... 100"});
  test::TempYaml same("iio:\n  device: bmi088\n  gyro_device: bmi088\n");
  test::expect_input_error([&] { load_imu_driver_options(same.path()); },
                           {"gyro_device", "leave it out"});
  test::TempYaml gap("iio:\n  pair_max_gap_s: 0\n");
  test::expect_input_error([&] { load_imu_driver_options(gap.path()); }, {"(0, 1]"});
}

TEST(ImuDriverOptions, IioSection) {
  test::TempYaml yaml(
      "imu:\n  backend: iio\niio:\n  device: iio:device3\n  trigger: t0\n"
      "  sampling_frequency_hz: 400\n  accel_channels: [in_accel_y, in_accel_x, in_accel_z]\n");
  const ImuDriverOptions o = load_imu_driver_options(yaml.path());
  EXPECT_EQ(o.backend, "iio");
  EXPECT_EQ(o.iio.device, "iio:device3");
  EXPECT_EQ(o.iio.trigger, "t0");
  EXPECT_EQ(o.iio.sampling_frequency_hz, 400);
  EXPECT_EQ(o.iio.accel[0], "in_accel_y");
  EXPECT_EQ(o.iio.gyro[2], "in_anglvel_z");
  EXPECT_TRUE(o.iio.gyro_device.empty());  // one device has both

  test::TempYaml split(
      "iio:\n  device: bmi088_accel\n  gyro_device: bmg160\n  gyro_trigger: bmg160-dev1\n"
      "  gyro_sampling_frequency_hz: 2000\n  pair_max_gap_s: 0.005\n");
  const ImuDriverOptions b = load_imu_driver_options(split.path());
  EXPECT_EQ(b.iio.gyro_device, "bmg160");
  EXPECT_EQ(b.iio.gyro_trigger, "bmg160-dev1");
  EXPECT_EQ(b.iio.gyro_sampling_frequency_hz, 2000);
  EXPECT_EQ(b.iio.pair_max_gap_s, 0.005);
}

TEST(ImuDriverOptions, OneMessageOnTheWire) {
  EXPECT_EQ(transmission_ns(kXsensMessageBytes, 921600), 509'982);  // 47 bytes, 10 bits each
  EXPECT_EQ(transmission_ns(kXsensMessageBytes, 115200), 4'079'861);
}

}  // namespace
}  // namespace hs
