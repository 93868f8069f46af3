#include "logger/logger_options.h"

#include <gtest/gtest.h>

#include "tests/config/config_test_util.h"

namespace hs {
namespace {

TEST(LoggerConfig, ShippedFileHoldsTheDefaults) {
  const LoggerOptions c = load_logger_options(HS_SOURCE_DIR "/config/logger.yaml");
  const LoggerOptions d;
  EXPECT_EQ(c.writer.directory, d.writer.directory);
  EXPECT_EQ(c.writer.max_file_bytes, d.writer.max_file_bytes);
  EXPECT_EQ(c.writer.max_file_duration_ns, d.writer.max_file_duration_ns);
  EXPECT_EQ(c.writer.flush_period_ns, d.writer.flush_period_ns);
  EXPECT_EQ(c.writer.min_free_bytes, d.writer.min_free_bytes);
  EXPECT_EQ(c.writer.on_disk_full, d.writer.on_disk_full);
  EXPECT_EQ(c.include, d.include);
  EXPECT_EQ(c.exclude, d.exclude);
  EXPECT_EQ(c.png_images, d.png_images);
}

TEST(LoggerConfig, ValuesAreReadAndBadOnesNamed) {
  const test::TempYaml ok(
      "logger:\n  include: [\"CAM_.*\", IMU]\n  exclude: [CAM_DEBUG]\n  png_images: true\n"
      "rotation:\n  max_file_mb: 64\n  max_file_s: 30\ndisk_guard:\n  min_free_mb: 10\n"
      "  on_full: delete_oldest\n");
  const LoggerOptions o = load_logger_options(ok.path());
  EXPECT_EQ(o.include, (std::vector<std::string>{"CAM_.*", "IMU"}));
  EXPECT_EQ(o.exclude, std::vector<std::string>{"CAM_DEBUG"});
  EXPECT_TRUE(o.png_images);
  EXPECT_EQ(o.writer.max_file_bytes, 64 << 20);
  EXPECT_EQ(o.writer.max_file_duration_ns, 30'000'000'000);
  EXPECT_EQ(o.writer.min_free_bytes, 10 << 20);
  EXPECT_EQ(o.writer.on_disk_full, DiskFullPolicy::kDeleteOldest);

  const test::TempYaml policy("disk_guard:\n  on_full: panic\n");
  test::expect_input_error([&] { load_logger_options(policy.path()); },
                           {policy.path() + ":2", "on_full"});
  const test::TempYaml typo("rotation:\n  max_file_megs: 5\n");
  test::expect_input_error([&] { load_logger_options(typo.path()); },
                           {"max_file_megs", "max_file_mb"});
}

}  // namespace
}  // namespace hs
