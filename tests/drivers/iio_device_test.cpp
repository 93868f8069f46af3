// IioDevice on a sysfs-like tree of real files, with a FIFO standing in for /dev/iio:deviceN
// (the kernel's own IIO device is exercised in the HIL harness).
#include "drivers/imu/iio_device.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/core/error.h"
#include "common/core/monotonic_clock.h"
#include "drivers/imu/iio_backend.h"
#include "tests/common/temp_dir.h"

namespace hs {
namespace {

void put(const std::string& path, const std::string& text) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path) << text << "\n";
}

std::string get(const std::string& path) {
  std::ifstream in(path);
  std::string s;
  std::getline(in, s);
  return s;
}

// Scan elements `channels` (index 0, 1, ...) of one type, each enabled or not, then the kernel's
// timestamp (disabled) after a gap in the indices.
void put_scan_elements(const std::string& dev, const std::vector<std::string>& channels,
                       const std::string& type, const std::string& enabled) {
  int index = 0;
  for (const std::string& c : channels) {
    put(dev + "/scan_elements/" + c + "_en", enabled);
    put(dev + "/scan_elements/" + c + "_index", std::to_string(index++));
    put(dev + "/scan_elements/" + c + "_type", type);
  }
  put(dev + "/scan_elements/in_timestamp_en", "0");
  put(dev + "/scan_elements/in_timestamp_index", std::to_string(index + 1));
  put(dev + "/scan_elements/in_timestamp_type", "le:s64/64>>0");
}

// An ADIS16448-like device: six 16-bit channels, a temperature one, the timestamp.
class FakeIio : public ::testing::Test {
 protected:
  void SetUp() override {
    root = dir.path() + "/sys";
    dev = root + "/iio:device1";
    put(root + "/iio:device0/name", "bmp280");
    put(dev + "/name", "adis16448");
    put(dev + "/buffer/enable", "1");  // left on by a reader that died
    put(dev + "/buffer/length", "0");
    put(dev + "/current_timestamp_clock", "realtime");
    put(dev + "/trigger/current_trigger", "");
    put(dev + "/sampling_frequency", "0");
    put(dev + "/in_accel_scale", "0.01");
    put(dev + "/in_anglvel_scale", "0.001");
    put(dev + "/in_anglvel_z_offset", "-2");
    put_scan_elements(dev,
                      {"in_anglvel_x", "in_anglvel_y", "in_anglvel_z", "in_accel_x", "in_accel_y",
                       "in_accel_z", "in_temp"},
                      "be:s16/16>>0", "1");
    put(root + "/trigger0/name", "adis16448-dev1");  // its data-ready trigger: no rate of its own
    ASSERT_EQ(::mkfifo((dir.path() + "/iio:device1").c_str(), 0600), 0);
    options.sysfs_root = root;
    options.dev_root = dir.path();
    options.trigger = "adis16448-dev1";
    options.sampling_frequency_hz = 200;
  }

  // One scan as the kernel lays it out: gyro xyz, accel xyz (big endian), pad, timestamp.
  static std::vector<uint8_t> scan(const std::array<int16_t, 6>& raw, int64_t t_ns) {
    std::vector<uint8_t> s(24, 0);
    for (int i = 0; i < 6; ++i) {
      s[2 * i] = static_cast<uint8_t>(static_cast<uint16_t>(raw[i]) >> 8);
      s[2 * i + 1] = static_cast<uint8_t>(raw[i] & 0xFF);
    }
    for (int i = 0; i < 8; ++i)
      s[16 + i] = static_cast<uint8_t>(static_cast<uint64_t>(t_ns) >> (8 * i));
    return s;
  }

  test::TempDir dir;
  std::string root, dev;
  IioOptions options;
};

TEST_F(FakeIio, ConfiguresTheDeviceAndDecodesScans) {
  auto device = std::make_unique<IioDevice>(options);
  EXPECT_EQ(device->name(), "iio:device1 (adis16448)");
  EXPECT_EQ(get(dev + "/buffer/enable"), "1");
  EXPECT_EQ(get(dev + "/buffer/length"), "256");
  EXPECT_EQ(get(dev + "/current_timestamp_clock"), "monotonic");
  EXPECT_EQ(get(dev + "/trigger/current_trigger"), "adis16448-dev1");
  EXPECT_EQ(get(dev + "/sampling_frequency"), "200");
  EXPECT_EQ(get(dev + "/scan_elements/in_temp_en"), "0");  // not configured: off
  EXPECT_EQ(get(dev + "/scan_elements/in_timestamp_en"), "1");
  EXPECT_EQ(device->scan_bytes(), 24u);

  const int writer = ::open((dir.path() + "/iio:device1").c_str(), O_WRONLY);
  ASSERT_GE(writer, 0);
  std::vector<uint8_t> bytes = scan({100, -200, 302, 981, 0, -981}, 1'000'000'000);
  const std::vector<uint8_t> second = scan({1, 2, 3, 4, 5, 6}, 1'005'000'000);
  bytes.insert(bytes.end(), second.begin(), second.end());
  // A scan and a half, then the rest: the partial scan waits for its bytes.
  ASSERT_EQ(::write(writer, bytes.data(), 36), 36);
  std::vector<ImuSample> samples;
  EXPECT_EQ(device->read(1000, &samples), IioDevice::ReadStatus::kData);
  ASSERT_EQ(samples.size(), 1u);
  EXPECT_EQ(samples[0].t_ns, 1'000'000'000);
  EXPECT_DOUBLE_EQ(samples[0].gyro.x(), 0.1);
  EXPECT_DOUBLE_EQ(samples[0].gyro.y(), -0.2);
  EXPECT_DOUBLE_EQ(samples[0].gyro.z(), 0.3);  // (302 - 2) * 0.001
  EXPECT_DOUBLE_EQ(samples[0].accel.x(), 9.81);
  EXPECT_DOUBLE_EQ(samples[0].accel.z(), -9.81);
  ASSERT_EQ(::write(writer, bytes.data() + 36, 12), 12);
  EXPECT_EQ(device->read(1000, &samples), IioDevice::ReadStatus::kData);
  ASSERT_EQ(samples.size(), 2u);
  EXPECT_EQ(samples[1].t_ns, 1'005'000'000);
  EXPECT_DOUBLE_EQ(samples[1].accel.y(), 0.05);
  EXPECT_EQ(device->read(10, &samples), IioDevice::ReadStatus::kTimeout);
  ::close(writer);  // the device goes away
  EXPECT_EQ(device->read(1000, &samples), IioDevice::ReadStatus::kLost);
  device.reset();
  EXPECT_EQ(get(dev + "/buffer/enable"), "0");  // stopped on close
}

TEST_F(FakeIio, ASoftwareTriggerSetsTheRate) {
  put(root + "/trigger1/name", "imu-timer");
  put(root + "/trigger1/sampling_frequency", "0");
  options.trigger = "imu-timer";
  IioDevice device(options);
  EXPECT_EQ(get(root + "/trigger1/sampling_frequency"), "200");
  EXPECT_EQ(get(dev + "/sampling_frequency"), "0");  // a device may refuse it (the IIO dummy)
}

TEST_F(FakeIio, ChannelsNotInTheScanAreAnErrorNamingWhatItHas) {
  options.gyro = {"in_anglvel_x", "in_anglvel_y", "in_magn_z"};
  try {
    IioDevice device(options);
    FAIL() << "opened";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("no scan element 'in_magn_z'"), std::string::npos) << what;
    EXPECT_NE(what.find("in_accel_x, in_accel_y"), std::string::npos) << what;
  }
  EXPECT_EQ(get(dev + "/buffer/enable"), "1");  // nothing touched
}

TEST_F(FakeIio, NoTimestampChannelIsAnError) {
  std::filesystem::remove(dev + "/scan_elements/in_timestamp_en");
  try {
    IioDevice device(options);
    FAIL() << "opened";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("kernel's timestamps"), std::string::npos) << e.what();
  }
}

TEST_F(FakeIio, AMissingDeviceNamesTheOnesThereAre) {
  options.device = "bmi160";
  try {
    IioDevice device(options);
    FAIL() << "opened";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("iio:device0 (bmp280), iio:device1 (adis16448)"),
              std::string::npos)
        << e.what();
  }
  options.device = "iio:device1";  // by its node name too
  EXPECT_NO_THROW(IioDevice device(options));
}

TEST_F(FakeIio, ABadScanTypeIsAnError) {
  put(dev + "/scan_elements/in_accel_y_type", "le:s16/12>>0");
  EXPECT_THROW(IioDevice device(options), InputError);
}

TEST(IioTimestampCheck, DropsBackwardsAndOffClockSamplesAndCountsGaps) {
  IioTimestampCheck check(2'000'000'000, 200);
  const int64_t now = 100'000'000'000;
  std::vector<ImuSample> samples(7);
  const int64_t times[] = {now - 50'000'000,          now - 45'000'000,
                           now - 45'000'000,           // repeated: dropped
                           now - 30'000'000,           // 2 samples missing before it
                           1'764'000'000'000'000'000,  // CLOCK_REALTIME: dropped
                           now - 3'000'000'000,        // older than the buffer: dropped
                           now - 25'000'000};
  for (size_t i = 0; i < samples.size(); ++i) samples[i].t_ns = times[i];
  check.filter(&samples, now);
  ASSERT_EQ(samples.size(), 4u);
  EXPECT_EQ(samples[2].t_ns, now - 30'000'000);
  EXPECT_EQ(samples[3].t_ns, now - 25'000'000);
  EXPECT_EQ(check.counters().backwards, 1);
  EXPECT_EQ(check.counters().off_clock, 2);
  EXPECT_EQ(check.counters().lost_samples, 2);
  EXPECT_NE(check.last_error().find("not on the camera's clock"), std::string::npos);
  check.restart();  // a reopened device may start anywhere after the last good one
  std::vector<ImuSample> again(1);
  again[0].t_ns = now - 40'000'000;
  check.filter(&again, now);
  EXPECT_EQ(again.size(), 1u);
}

// A BMI088: accelerometer and gyroscope as two IIO devices (bmi088_accel, bmg160), each with
// x y z (le:s16) and its timestamp, at 100 and 200 Hz.
TEST(IioBackendSplit, PairsAnAccelerometerDeviceWithAGyroscopeDevice) {
  test::TempDir dir;
  const std::string root = dir.path() + "/sys";
  const auto device = [&](const std::string& node, const std::string& name, const char* type) {
    const std::string d = root + "/" + node;
    put(d + "/name", name);
    put(d + "/buffer/enable", "0");
    put(d + "/sampling_frequency", "0");
    put(d + "/trigger/current_trigger", "");
    put(d + "/in_" + std::string(type) + "_scale", "0.01");
    const std::string t = "in_" + std::string(type);
    put_scan_elements(d, {t + "_x", t + "_y", t + "_z"}, "le:s16/16>>0", "0");
    EXPECT_EQ(::mkfifo((dir.path() + "/" + node).c_str(), 0600), 0);
  };
  device("iio:device0", "bmi088_accel", "accel");
  device("iio:device1", "bmg160", "anglvel");
  IioOptions options;
  options.sysfs_root = root;
  options.dev_root = dir.path();
  options.device = "bmi088_accel";
  options.sampling_frequency_hz = 100;
  options.gyro_device = "bmg160";
  options.gyro_sampling_frequency_hz = 200;

  IioBackend backend(options);
  backend.open();
  EXPECT_EQ(backend.device(), "iio:device0 (bmi088_accel) + iio:device1 (bmg160)");
  EXPECT_EQ(get(root + "/iio:device0/sampling_frequency"), "100");
  EXPECT_EQ(get(root + "/iio:device1/sampling_frequency"), "200");
  EXPECT_EQ(get(root + "/iio:device0/scan_elements/in_accel_z_en"), "1");
  EXPECT_EQ(get(root + "/iio:device1/scan_elements/in_anglvel_z_en"), "1");

  // 16-byte scans: x y z, pad, timestamp. The gyroscope starts 5 ms before the accelerometer.
  const auto scan = [](int16_t x, int64_t t_ns) {
    std::vector<uint8_t> s(16, 0);
    s[0] = static_cast<uint8_t>(x & 0xFF);
    s[1] = static_cast<uint8_t>(static_cast<uint16_t>(x) >> 8);
    for (int i = 0; i < 8; ++i)
      s[8 + i] = static_cast<uint8_t>(static_cast<uint64_t>(t_ns) >> (8 * i));
    return s;
  };
  const int64_t t0 = monotonic_ns() - 500'000'000;
  std::vector<uint8_t> accel_bytes, gyro_bytes;
  for (int i = 0; i < 4; ++i) {
    const auto s = scan(static_cast<int16_t>(100 * i), t0 + 10'000'000 * i);
    accel_bytes.insert(accel_bytes.end(), s.begin(), s.end());
  }
  for (int i = 0; i < 8; ++i) {
    const auto s = scan(static_cast<int16_t>(i), t0 - 5'000'000 + 5'000'000 * i);
    gyro_bytes.insert(gyro_bytes.end(), s.begin(), s.end());
  }
  const int accel_fd = ::open((dir.path() + "/iio:device0").c_str(), O_WRONLY);
  const int gyro_fd = ::open((dir.path() + "/iio:device1").c_str(), O_WRONLY);
  ASSERT_GE(accel_fd, 0);
  ASSERT_GE(gyro_fd, 0);
  ASSERT_EQ(::write(gyro_fd, gyro_bytes.data(), gyro_bytes.size()),
            static_cast<ssize_t>(gyro_bytes.size()));
  std::vector<ImuSample> samples;
  // Read, but nothing paired before the accelerometer's first sample.
  EXPECT_EQ(backend.read(100, &samples), ImuBackend::ReadStatus::kData);
  EXPECT_TRUE(samples.empty());
  ASSERT_EQ(::write(accel_fd, accel_bytes.data(), accel_bytes.size()),
            static_cast<ssize_t>(accel_bytes.size()));
  EXPECT_EQ(backend.read(1000, &samples), ImuBackend::ReadStatus::kData);
  // Gyroscope times t0 ... t0 + 30 ms (the first, before the accelerometer, dropped as leading).
  ASSERT_EQ(samples.size(), 7u);
  EXPECT_EQ(samples[0].t_ns, t0);
  EXPECT_EQ(samples[1].t_ns, t0 + 5'000'000);
  EXPECT_DOUBLE_EQ(samples[1].gyro.x(), 0.02);  // raw 2 * 0.01
  EXPECT_DOUBLE_EQ(samples[1].accel.x(), 0.5);  // halfway from 0 to 1 m/s^2
  EXPECT_DOUBLE_EQ(samples[6].accel.x(), 3.0);
  const ImuBackend::Counters c = backend.counters();
  const auto counter = [&](const std::string& name) {
    for (const auto& [n, v] : c)
      if (n == name) return v;
    return int64_t{-1};
  };
  EXPECT_EQ(counter("paired_samples"), 7);
  EXPECT_EQ(counter("leading_gyro_samples"), 1);
  EXPECT_EQ(counter("unpaired_gyro_samples"), 0);
  EXPECT_EQ(backend.bad_input(), 0);
  ::close(gyro_fd);  // one of the two gone: the IMU is lost
  EXPECT_EQ(backend.read(1000, &samples), ImuBackend::ReadStatus::kLost);
  ::close(accel_fd);
  backend.close();
  EXPECT_EQ(get(root + "/iio:device1/buffer/enable"), "0");
}

}  // namespace
}  // namespace hs
