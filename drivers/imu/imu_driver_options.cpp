#include "drivers/imu/imu_driver_options.h"

#include "common/config/process_section.h"
#include "drivers/imu/serial_port.h"

namespace hs {

int64_t transmission_ns(int message_bytes, int baud) {
  return static_cast<int64_t>(message_bytes) * 10 * 1'000'000'000 / baud;  // 8N1: 10 bits a byte
}

ImuDriverOptions load_imu_driver_options(const std::string& path) {
  ImuDriverOptions o;
  ConfigSection top = ConfigSection::load(path);
  top.section("imu", [&](ConfigSection& s) {
    s.read("backend", o.backend);
    if (o.backend != "xsens" && o.backend != "iio")
      s.fail("backend", "must be 'xsens' (the Xsens MT serial protocol) or 'iio' (Linux IIO)");
    s.read("device", o.device);
    if (o.device.empty()) s.fail("device", "must name a serial device");
    s.read("baud", o.baud);
    try {
      baud_constant(o.baud);
    } catch (const std::exception& e) {
      s.fail("baud", e.what());
    }
    s.read("batch_size", o.batch_size);
    if (o.batch_size < 1 || o.batch_size > 100) s.fail("batch_size", "must be 1 ... 100");
    s.read_period("reconnect_period_s", o.reconnect_period_ns);
  });
  top.section("iio", [&](ConfigSection& s) {
    IioOptions& iio = o.iio;
    s.read("device", iio.device);
    if (iio.device.empty()) s.fail("device", "must name an IIO device (its name or iio:deviceN)");
    s.read("trigger", iio.trigger);
    s.read("sampling_frequency_hz", iio.sampling_frequency_hz);
    if (iio.sampling_frequency_hz < 0) s.fail("sampling_frequency_hz", "must be >= 0");
    s.read("buffer_length", iio.buffer_length);
    if (iio.buffer_length < 2 || iio.buffer_length > 65536)
      s.fail("buffer_length", "must be 2 ... 65536");
    for (const auto& [key, axes] :
         {std::pair{"accel_channels", &iio.accel}, std::pair{"gyro_channels", &iio.gyro}}) {
      std::vector<std::string> names;
      if (!s.read(key, names)) continue;
      if (names.size() != 3) s.fail(key, "must list 3 scan elements (x, y, z)");
      for (int i = 0; i < 3; ++i) (*axes)[i] = names[i];
    }
    s.read("gyro_device", iio.gyro_device);
    s.read("gyro_trigger", iio.gyro_trigger);
    s.read("gyro_sampling_frequency_hz", iio.gyro_sampling_frequency_hz);
    if (iio.gyro_sampling_frequency_hz < 0) s.fail("gyro_sampling_frequency_hz", "must be >= 0");
    s.read("pair_max_gap_s", iio.pair_max_gap_s);
    if (!(iio.pair_max_gap_s > 0 && iio.pair_max_gap_s <= 1))
      s.fail("pair_max_gap_s", "must be in (0, 1]");
    if (iio.gyro_device == iio.device)
      s.fail("gyro_device", "is the accelerometer's device: leave it out when one has both");
  });
  top.section("clock", [&](ConfigSection& s) { s.read_period("window_s", o.clock.window_ns); });
  read_process_tail(top, o.heartbeat_period_ns, o.channels);
  return o;
}

}  // namespace hs
