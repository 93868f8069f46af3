// hs-imu: the IMU driver. Reads an Xsens MT IMU over a serial line or an IMU with a Linux IIO
// driver and publishes IMU batches on the host's CLOCK_MONOTONIC (the camera's clock), with
// HEARTBEAT.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "common/core/stop_signal.h"
#include "common/lcm/lcm_connection.h"
#include "drivers/imu/imu_driver_node.h"
#include "drivers/imu/imu_driver_options.h"

int main(int argc, char** argv) {
  CLI::App app{
      "hs-imu: IMU driver (Xsens MT serial or Linux IIO) publishing IMU on CLOCK_MONOTONIC"};
  app.footer(R"(
xsens: each sample's time is its device time (SampleTimeFine, 10 kHz) mapped to CLOCK_MONOTONIC
by the least-delayed samples of the last clock.window_s, less one message's time on the wire.
Messages that fail their checksum, are malformed or lack time, acceleration or rate of turn are
counted and dropped; samples whose device time does not advance are dropped; packet-counter gaps
are counted as lost.
iio: the kernel's timestamp channel on CLOCK_MONOTONIC (current_timestamp_clock); configured
channels that are not scan elements of the device are an error naming the ones it has; samples
whose timestamp does not advance or is off CLOCK_MONOTONIC are counted and dropped.
A missing, busy or unplugged device is retried every reconnect period (HEARTBEAT state ERROR
meanwhile). Stops on SIGINT/SIGTERM.)");
  std::string config, device, url = hs::default_lcm_url();
  app.add_option("--config", config, "driver config (config/imu.yaml; default: built in)");
  app.add_option("--device", device, "serial device or IIO device (overrides the config's)");
  app.add_option("--lcm-url", url, "LCM URL ($LCM_DEFAULT_URL or the project default)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  hs::install_stop_signals();
  try {
    hs::ImuDriverOptions options;
    if (!config.empty()) options = hs::load_imu_driver_options(config);
    if (!device.empty()) (options.backend == "iio" ? options.iio.device : options.device) = device;
    auto lcm = hs::connect_lcm(url);
    hs::ImuDriverNode node(*lcm, options);
    std::printf("hs-imu: reading %s (%s), publishing %s on %s\n", node.backend().device().c_str(),
                options.backend.c_str(), options.channels.imu.c_str(), url.c_str());
    std::fflush(stdout);
    node.run();
    const hs::ImuDriverStats& s = node.stats();
    std::string counters;
    for (const auto& [name, value] : node.backend().counters())
      counters += " " + name + "=" + std::to_string(value);
    std::printf("hs-imu: %lld samples in %lld messages; %lld connects, %lld device losses;%s\n",
                static_cast<long long>(s.samples_published),
                static_cast<long long>(s.messages_published), static_cast<long long>(s.connects),
                static_cast<long long>(s.device_lost), counters.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hs-imu: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
