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
  test::TempYaml baud("imu:\n  baud: 1000\n");
  test::expect_input_error([&] { load_imu_driver_options(baud.path()); },
                           {baud.path() + ":2", "unsupported baud rate 1000"});
  test::TempYaml batch("imu:\n  batch_size: 0\n");
  test::expect_input_error([&] { load_imu_driver_options(batch.path()); }, {"1 ... 100"});
}

TEST(ImuDriverOptions, OneMessageOnTheWire) {
  EXPECT_EQ(transmission_ns(kXsensMessageBytes, 921600), 509'982);  // 47 bytes, 10 bits each
  EXPECT_EQ(transmission_ns(kXsensMessageBytes, 115200), 4'079'861);
}

}  // namespace
}  // namespace hs
