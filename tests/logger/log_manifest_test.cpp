#include "logger/log_manifest.h"

#include <gtest/gtest.h>

#include "hsslam/heartbeat_t.hpp"
#include "hsslam/odometry_t.hpp"
#include "tests/lcm/lcm_test_util.h"

namespace hs {
namespace {

std::vector<uint8_t> pose(int64_t seq) {
  hsslam::odometry_t m{};
  m.t_ns = 1000 + seq;
  m.seq = seq;
  return test::encode_bytes(m);
}

TEST(LogManifest, SeqOfTheSequencedTypesOnly) {
  EXPECT_EQ(message_seq(pose(42).data(), pose(42).size()), 42);
  hsslam::heartbeat_t hb{};
  hb.t_ns = 7;
  const std::vector<uint8_t> b = test::encode_bytes(hb);
  EXPECT_EQ(message_seq(b.data(), b.size()), -1);
  EXPECT_EQ(message_seq(b.data(), 10), -1);  // too short for any
}

TEST(LogManifest, GapsInSeqAreMessagesLostUpstream) {
  LogManifest m;
  int64_t utime = 100;
  for (const int64_t seq : {0, 1, 2, 5, 6, 10, 0, 1}) {  // lost 3, 4 and 7-9; then a restart
    const std::vector<uint8_t> b = pose(seq);
    m.add("POSE", utime += 10, static_cast<int64_t>(b.size()), message_seq(b.data(), b.size()));
  }
  m.add("HEARTBEAT", 95, 40, -1);
  const ChannelStats& p = m.channels().at("POSE");
  EXPECT_EQ(p.messages, 8);
  EXPECT_EQ(p.lost, 5);
  EXPECT_EQ(p.seq_restarts, 1);
  ASSERT_EQ(p.gaps.size(), 2u);
  EXPECT_EQ(p.gaps[0], std::make_pair(int64_t{2}, int64_t{5}));
  EXPECT_EQ(p.gaps[1], std::make_pair(int64_t{6}, int64_t{10}));
  EXPECT_EQ(p.first_utime, 110);
  EXPECT_EQ(p.last_utime, 180);
  EXPECT_FALSE(m.channels().at("HEARTBEAT").sequenced);

  const nlohmann::json j = m.to_json();
  EXPECT_EQ(j["messages"], 9);
  EXPECT_EQ(j["first_utime"], 95);
  EXPECT_EQ(j["last_utime"], 180);
  EXPECT_EQ(j["channels"]["POSE"]["lost_upstream"], 5);
  EXPECT_FALSE(j["channels"]["HEARTBEAT"].contains("lost_upstream"));
}

}  // namespace
}  // namespace hs
