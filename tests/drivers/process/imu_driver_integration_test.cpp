// hs-imu against a real kernel tty: a pty pair whose master plays an Xsens IMU at 200 Hz, with
// corrupted messages and gaps, then an unplug (hangup) and a new device behind the same
// (symlinked) name. IMU and HEARTBEAT are checked over udpm on loopback.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <mutex>
#include <thread>

#include "common/core/monotonic_clock.h"
#include "common/lcm/convert.h"
#include "common/lcm/decode.h"
#include "drivers/imu/xsens_protocol.h"
#include "hsslam/heartbeat_t.hpp"
#include "tests/common/child_process.h"
#include "tests/common/process_test_util.h"
#include "tests/common/pty_pair.h"
#include "tests/dataset/dataset_test_util.h"

namespace hs {
namespace {

namespace fs = std::filesystem;
using test::ChildProcess;
using test::wait_for;

struct Pty : test::PtyPair {
  void send(const XsensSample& s) { PtyPair::send(encode_xsens_mtdata2(s)); }
  void send_corrupted(const XsensSample& s) {
    std::vector<uint8_t> b = encode_xsens_mtdata2(s);
    b[25] ^= 0x10;
    PtyPair::send(b);
  }
};

struct Heard {
  std::mutex mutex;
  std::vector<ImuSample> samples;
  hsslam::heartbeat_t heartbeat{};
  int64_t counter(const std::string& name) {
    std::lock_guard<std::mutex> lock(mutex);
    for (size_t i = 0; i < heartbeat.counter_names.size(); ++i)
      if (heartbeat.counter_names[i] == name) return heartbeat.counter_values[i];
    return -1;
  }
  size_t count() {
    std::lock_guard<std::mutex> lock(mutex);
    return samples.size();
  }
  static void on(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Heard* self) {
    std::lock_guard<std::mutex> lock(self->mutex);
    if (channel == "IMU") {
      const auto msg = decode_message<hsslam::imu_batch_t>(rbuf->data, rbuf->data_size, channel);
      for (const ImuSample& s : imu_batch_from_msg(msg, channel)) self->samples.push_back(s);
    } else {
      auto hb = decode_message<hsslam::heartbeat_t>(rbuf->data, rbuf->data_size, channel);
      if (hb.process == "hs-imu") self->heartbeat = std::move(hb);
    }
  }
};

// Sample i, stamped with the device's clock: 10 kHz ticks since `device_start_ns`, running at the
// real rate like a device's crystal.
XsensSample sample(int i, int64_t device_start_ns) {
  XsensSample s;
  s.packet_counter = static_cast<uint16_t>(i);
  s.sample_time_fine = static_cast<uint32_t>((monotonic_ns() - device_start_ns) / 100'000);
  s.accel = Eigen::Vector3d(0.25 * i, 0, 9.75);
  s.gyro = Eigen::Vector3d(0, 0.001 * i, 0);
  return s;
}

TEST(ImuDriverProcess, PublishesGoodSamplesOnTheHostClockAndSurvivesAnUnplug) {
  test::TempDir dir;
  const std::string link = dir.path() + "/imu";  // as /dev/serial/by-id/... would be
  auto pty = std::make_unique<Pty>();
  fs::create_symlink(pty->name, link);
  const std::string url = test::private_udpm_url(41);
  lcm::LCM lcm(url);
  ASSERT_TRUE(lcm.good());
  Heard heard;
  lcm.subscribeFunction("IMU|HEARTBEAT", &Heard::on, &heard);
  std::atomic<bool> listening{true};
  std::thread receiver([&] {
    while (listening) lcm.handleTimeout(20);
  });
  struct Join {  // also when an assertion returns early
    std::atomic<bool>& flag;
    std::thread& thread;
    ~Join() {
      flag = false;
      thread.join();
    }
  } join{listening, receiver};
  ChildProcess imu({HS_IMU, "--device", link, "--lcm-url", url}, dir.path() + "/imu.txt");
  ASSERT_TRUE(wait_for([&] { return heard.counter("connects") == 1; }, 10)) << imu.output();

  // 200 samples at 200 Hz: 100 and 101 never sent (lost upstream), every 25th corrupted. Lost as
  // counted from the packet counter: those two and the corrupted ones but the last (199), which
  // no later sample reveals.
  std::vector<int64_t> sent_at(200, 0);
  const int64_t device_start = monotonic_ns() - 3'000'000'000;  // powered on 3 s ago
  for (int i = 0; i < 200; ++i) {
    if (i != 100 && i != 101) {
      sent_at[i] = monotonic_ns();
      if (i % 25 == 24)
        pty->send_corrupted(sample(i, device_start));
      else
        pty->send(sample(i, device_start));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(wait_for(
      [&] {
        return heard.count() >= 190 && heard.counter("lost_samples") == 9 &&
               heard.counter("bad_checksum") == 8;
      },
      5))
      << heard.count() << " samples\n"
      << imu.output();
  std::vector<ImuSample> first;
  {
    std::lock_guard<std::mutex> lock(heard.mutex);
    first = heard.samples;
  }
  ASSERT_EQ(first.size(), 190u);
  int checked = 0;
  for (size_t k = 0; k < first.size(); ++k) {
    const int i = static_cast<int>(std::lround(first[k].accel.x() / 0.25));
    ASSERT_TRUE(i % 25 != 24 && i != 100 && i != 101) << "a dropped sample was published: " << i;
    EXPECT_DOUBLE_EQ(first[k].gyro.y(), static_cast<float>(0.001 * i));
    if (k > 0) {
      EXPECT_GT(first[k].t_ns, first[k - 1].t_ns);
    }
    // On the host clock: close to when the sample was written (after the first ones settle
    // the least-delay estimate).
    if (k >= 20) {
      EXPECT_NEAR(static_cast<double>(first[k].t_ns - sent_at[i]) / 1e6, 0.0, 3.0) << i;
      ++checked;
    }
  }
  EXPECT_GT(checked, 150);

  // Unplugged: said on HEARTBEAT; a new device behind the same name is found without a restart.
  pty->close();
  ASSERT_TRUE(wait_for([&] { return heard.counter("device_lost") == 1; }, 5)) << imu.output();
  {
    std::lock_guard<std::mutex> lock(heard.mutex);
    EXPECT_EQ(heard.heartbeat.state, hsslam::heartbeat_t::ERROR);
    EXPECT_NE(heard.heartbeat.message.find("lost"), std::string::npos) << heard.heartbeat.message;
  }
  pty = std::make_unique<Pty>();
  fs::remove(link);
  fs::create_symlink(pty->name, link);
  ASSERT_TRUE(wait_for([&] { return heard.counter("connects") == 2; }, 10)) << imu.output();
  const int64_t restarted = monotonic_ns();  // the device's counters restart
  for (int i = 0; i < 20; ++i) {
    pty->send(sample(i, restarted));
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(wait_for([&] { return heard.count() >= 210; }, 5)) << imu.output();
  {
    std::lock_guard<std::mutex> lock(heard.mutex);
    ASSERT_EQ(heard.samples.size(), 210u);
    EXPECT_GT(heard.samples[190].t_ns, heard.samples[189].t_ns) << "time went on";
  }
  imu.signal(SIGINT);
  EXPECT_EQ(imu.wait(), 0) << imu.output();
  EXPECT_NE(imu.output().find("210 samples"), std::string::npos) << imu.output();
  EXPECT_NE(imu.output().find("bad_checksum=8 "), std::string::npos) << imu.output();
}

}  // namespace
}  // namespace hs
