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
    if (o.backend != "xsens") s.fail("backend", "must be 'xsens' (the Xsens MT serial protocol)");
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
  top.section("clock", [&](ConfigSection& s) { s.read_period("window_s", o.clock.window_ns); });
  read_process_tail(top, o.heartbeat_period_ns, o.channels);
  return o;
}

}  // namespace hs
