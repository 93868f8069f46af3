#include "mapper/keyframe_from_msg.h"

#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "common/core/error.h"
#include "common/lcm/decode.h"
#include "tests/mapper/keyframe_test_util.h"

namespace hs {
namespace {

using test::keyframe_msg;
using test::keyframe_time;

// Through the LCM wire format, as the mapper receives it.
hsslam::keyframe_t round_trip(const hsslam::keyframe_t& msg) {
  std::vector<uint8_t> bytes(static_cast<size_t>(msg.getEncodedSize()));
  EXPECT_EQ(msg.encode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  return decode_message<hsslam::keyframe_t>(bytes.data(), bytes.size(), "KEYFRAME");
}

TEST(KeyframeFromMsg, ConvertsAValidMessage) {
  const std::vector<int64_t> points{10, 11, 12};
  const hsslam::keyframe_t msg = keyframe_msg(5, 4, points, 2);
  const MapperKeyframe kf = keyframe_from_msg(round_trip(msg), "KEYFRAME");
  EXPECT_EQ(kf.id, 5);
  EXPECT_EQ(kf.prev_id, 4);
  EXPECT_EQ(kf.map_id, 2);
  EXPECT_EQ(kf.state.t_ns, keyframe_time(5));
  EXPECT_DOUBLE_EQ(kf.state.p_w_b.x(), msg.pose.p_w_b[0]);
  EXPECT_DOUBLE_EQ(kf.state.v_w.x(), msg.pose.v_w[0]);
  ASSERT_EQ(kf.keypoints.size(), points.size() + 1);
  ASSERT_EQ(kf.descriptors.size(), kf.keypoints.size());
  for (size_t i = 0; i < kf.keypoints.size(); ++i) {
    EXPECT_EQ(kf.keypoints[i].point_id, msg.keypoints[i].map_point_id);
    EXPECT_FLOAT_EQ(kf.keypoints[i].u, msg.keypoints[i].u);
    EXPECT_FLOAT_EQ(kf.keypoints[i].depth, msg.keypoints[i].depth);
    EXPECT_TRUE(
        std::equal(kf.descriptors[i].begin(), kf.descriptors[i].end(), msg.descriptors[i].begin()));
  }
  ASSERT_EQ(kf.point_positions.size(), points.size());
  EXPECT_DOUBLE_EQ(kf.point_positions.at(11).x(), msg.points[1].p_w[0]);
  ASSERT_EQ(kf.imu.size(), msg.imu.size());
  EXPECT_LT(kf.imu.front().t_ns, keyframe_time(4));  // the brackets of the interval
  EXPECT_GE(kf.imu.back().t_ns, keyframe_time(5));
  EXPECT_DOUBLE_EQ(kf.imu[3].accel.z(), msg.imu[3].accel[2]);
}

TEST(KeyframeFromMsg, AcceptsAFirstKeyframeWithoutImu) {
  const MapperKeyframe kf = keyframe_from_msg(keyframe_msg(0, -1, {1, 2}), "KEYFRAME");
  EXPECT_EQ(kf.prev_id, -1);
  EXPECT_TRUE(kf.imu.empty());
}

struct Corruption {
  const char* name;
  std::function<void(hsslam::keyframe_t&)> apply;
  const char* expected;  // in the error message
};

TEST(KeyframeFromMsg, RejectsMalformedMessagesNamingChannelAndKeyframe) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Corruption> cases = {
      {"NaN position", [&](auto& m) { m.pose.p_w_b[1] = nan; }, "p_w_b"},
      {"NaN gyro bias", [&](auto& m) { m.pose.gyro_bias[0] = nan; }, "gyro_bias"},
      {"non-unit quaternion", [](auto& m) { m.pose.q_w_b[0] = 2.0; }, "unit quaternion"},
      {"times differ", [](auto& m) { m.t_ns += 1; }, "differs from pose.t_ns"},
      {"prev not older", [](auto& m) { m.prev_keyframe_id = 5; }, "prev_keyframe_id"},
      {"keypoint count", [](auto& m) { m.num_keypoints += 1; }, "num_keypoints"},
      {"descriptor count", [](auto& m) { m.descriptors.pop_back(); }, "num_keypoints"},
      {"short descriptor", [](auto& m) { m.descriptors[1].resize(31); }, "31 bytes"},
      {"point count", [](auto& m) { m.num_points -= 1; }, "num_points"},
      {"unknown point", [](auto& m) { m.keypoints[0].map_point_id = 999; }, "999, which is not"},
      {"point listed twice",
       [](auto& m) {
         m.points.push_back(m.points[0]);
         m.num_points += 1;
       },
       "listed twice"},
      {"point not observed",
       [](auto& m) {
         m.points.push_back({77, {0.0, 0.0, 1.0}});
         m.num_points += 1;
       },
       "observed by no keypoint"},
      {"point observed twice",
       [](auto& m) { m.keypoints[2].map_point_id = m.keypoints[0].map_point_id; }, "both observe"},
      {"infinite point",
       [](auto& m) { m.points[0].p_w[2] = std::numeric_limits<double>::infinity(); },
       "non-finite p_w"},
      {"NaN pixel", [&](auto& m) { m.keypoints[1].u = static_cast<float>(nan); }, "non-finite u"},
      {"zero depth", [](auto& m) { m.keypoints[0].depth = 0.f; }, "depth"},
      {"bad u_right", [](auto& m) { m.keypoints[0].u_right = -5.f; }, "right pixel"},
      {"half a right pixel", [](auto& m) { m.keypoints[0].v_right = -1.f; }, "right pixel"},
      {"negative octave", [](auto& m) { m.keypoints[0].octave = -1; }, "octave"},
      {"IMU count", [](auto& m) { m.num_imu -= 1; }, "num_imu"},
      {"IMU out of order", [](auto& m) { std::swap(m.imu[2], m.imu[3]); }, "does not increase"},
      {"NaN gyro", [&](auto& m) { m.imu[4].gyro[1] = nan; }, "gyro"},
      {"IMU past the keyframe",
       [](auto& m) {
         m.imu.push_back(m.imu.back());
         m.imu.back().t_ns += test::kImuStepNs;
         m.num_imu += 1;
       },
       "extend past"},
  };
  for (const Corruption& c : cases) {
    SCOPED_TRACE(c.name);
    hsslam::keyframe_t msg = keyframe_msg(5, 4, {10, 11, 12});
    c.apply(msg);
    try {
      keyframe_from_msg(msg, "KEYFRAME");
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("KEYFRAME: keyframe 5", 0), 0u) << what;
      EXPECT_NE(what.find(c.expected), std::string::npos) << what;
    }
  }
}

// A lost tracker's frame: a keyframe of the map it was lost in, and the map id it offers.
TEST(RelocRequestFromMsg, ChecksTheFrameAndTheOfferedMapId) {
  hsslam::reloc_request_t msg{};
  msg.seq = 7;
  msg.next_map_id = 3;
  msg.frame = keyframe_msg(0, -1, {1, 2});
  const RelocRequest r = reloc_request_from_msg(msg, "RELOC_REQUEST");
  EXPECT_EQ(r.seq, 7);
  EXPECT_EQ(r.next_map_id, 3);
  EXPECT_EQ(r.frame.keypoints.size(), msg.frame.keypoints.size());

  msg.next_map_id = msg.frame.map_id;
  try {
    reloc_request_from_msg(msg, "RELOC_REQUEST");
    ADD_FAILURE() << "accepted its own map id";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("RELOC_REQUEST: reloc_request_t seq 7: next_map_id"),
              std::string::npos)
        << e.what();
  }
  msg.next_map_id = 3;
  msg.frame.num_keypoints += 1;  // the frame is checked as a keyframe
  EXPECT_THROW(reloc_request_from_msg(msg, "RELOC_REQUEST"), InputError);
}

}  // namespace
}  // namespace hs
