#pragma once
// The Xsens MT serial protocol (Xbus, as the MTi 1/10/100/600 series speak it), the serial IMU
// backend of hs-imu. A message is
//   FA (preamble)  FF (bus id)  MID  LEN [LENH LENL if LEN = FF]  DATA[len]  CS
// where the bytes from the bus id to CS sum to 0 mod 256. MID 0x36 (MTData2) carries data packets
// XDI(2) SIZE(1) VALUE[size], big-endian; hs-imu uses PacketCounter (0x1020, uint16),
// SampleTimeFine (0x1060, uint32 at 10 kHz), Acceleration (0x4020, 3 float32, m/s^2) and
// RateOfTurn (0x8020, 3 float32, rad/s). Other messages and data packets are skipped.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace hs {

struct XsensSample {
  uint16_t packet_counter = 0;
  uint32_t sample_time_fine = 0;                    // device clock, 10 kHz, wraps at 2^32
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();  // m/s^2
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();   // rad/s
};

struct XsensCounters {
  int64_t samples = 0;         // MTData2 messages with everything hs-imu needs
  int64_t bad_checksum = 0;    // dropped
  int64_t malformed = 0;       // a data packet overrunning its message, or a length too large
  int64_t incomplete = 0;      // MTData2 without time, acceleration or rate of turn: dropped
  int64_t other_messages = 0;  // valid, not MTData2 (acks, errors): skipped
  int64_t skipped_bytes = 0;   // bytes outside any valid message (noise, a resync)

  XsensCounters& operator+=(const XsensCounters& o) {
    samples += o.samples;
    bad_checksum += o.bad_checksum;
    malformed += o.malformed;
    incomplete += o.incomplete;
    other_messages += o.other_messages;
    skipped_bytes += o.skipped_bytes;
    return *this;
  }
};

constexpr double kXsensSampleTimeHz = 10'000.0;

// Turns a byte stream into samples; bytes may come in any pieces. Never throws on bad input:
// a message that fails its checksum is counted and the search for the next preamble resumes
// one byte after it, so a corrupted message never hides the good one behind it.
class XsensParser {
 public:
  // Appends the complete, valid samples found so far to `out`.
  void feed(const uint8_t* data, size_t size, std::vector<XsensSample>* out);
  const XsensCounters& counters() const { return counters_; }
  // The reason the last message was dropped (empty: none yet).
  const std::string& last_error() const { return last_error_; }

 private:
  void parse_mtdata2(const uint8_t* data, size_t size, std::vector<XsensSample>* out);

  std::vector<uint8_t> buffer_;
  XsensCounters counters_;
  std::string last_error_;
};

// An MTData2 message holding `s` (for simulators and tests).
std::vector<uint8_t> encode_xsens_mtdata2(const XsensSample& s);

}  // namespace hs
