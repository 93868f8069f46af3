#pragma once
// A short simulated stereo-inertial sequence as the LCM messages a log replay would send (IMU
// batches before the frame they cover), with the tracker library's own results on it.
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "common/core/types.h"
#include "tracker/tracker.h"

namespace hs::test {

struct WireMessage {
  std::string channel;
  std::vector<uint8_t> bytes;
  bool is_frame = false;
};

struct SimSequence {
  TrackerOptions options;  // defaults with the scenario's calibration
  std::vector<WireMessage> messages;
  std::vector<ImuSample> imu;
  std::vector<FrameResult> reference;  // Tracker::track on the same input, per frame
};

// room_mav for `duration_s` seconds.
SimSequence make_sim_sequence(double duration_s);

template <class Msg>
std::vector<uint8_t> encode(const Msg& msg) {
  std::vector<uint8_t> bytes(static_cast<size_t>(msg.getEncodedSize()));
  msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

}  // namespace hs::test
