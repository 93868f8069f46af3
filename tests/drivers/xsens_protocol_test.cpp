#include "drivers/imu/xsens_protocol.h"

#include <gtest/gtest.h>

namespace hs {
namespace {

XsensSample sample(int i) {
  XsensSample s;
  s.packet_counter = static_cast<uint16_t>(i);
  s.sample_time_fine = 1000u + 50u * static_cast<uint32_t>(i);
  s.accel = Eigen::Vector3d(0.25 * i, -9.8125, 0.5);
  s.gyro = Eigen::Vector3d(0.001 * i, 0.0, -0.125);
  return s;
}

std::vector<XsensSample> parse(XsensParser& p, const std::vector<uint8_t>& bytes) {
  std::vector<XsensSample> out;
  p.feed(bytes.data(), bytes.size(), &out);
  return out;
}

void append(std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  a.insert(a.end(), b.begin(), b.end());
}

TEST(XsensProtocol, EncodedSamplesParseBackExactly) {
  const std::vector<uint8_t> msg = encode_xsens_mtdata2(sample(3));
  EXPECT_EQ(msg.size(), 47u);  // kXsensMessageBytes
  EXPECT_EQ(msg[0], 0xFA);
  EXPECT_EQ(msg[2], 0x36);
  XsensParser p;
  const auto out = parse(p, msg);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].packet_counter, 3);
  EXPECT_EQ(out[0].sample_time_fine, 1150u);
  EXPECT_EQ(out[0].accel, sample(3).accel);  // float-exact values
  EXPECT_EQ(out[0].gyro.z(), -0.125);
  EXPECT_EQ(p.counters().samples, 1);
  EXPECT_EQ(p.counters().skipped_bytes, 0);
}

TEST(XsensProtocol, BytesMayArriveInAnyPieces) {
  std::vector<uint8_t> stream;
  for (int i = 0; i < 20; ++i) append(stream, encode_xsens_mtdata2(sample(i)));
  XsensParser p;
  std::vector<XsensSample> out;
  for (size_t i = 0; i < stream.size();) {
    const size_t n = std::min<size_t>(1 + i % 7, stream.size() - i);  // 1..7 bytes at a time
    p.feed(stream.data() + i, n, &out);
    i += n;
  }
  ASSERT_EQ(out.size(), 20u);
  for (int i = 0; i < 20; ++i) EXPECT_EQ(out[i].packet_counter, i);
  EXPECT_EQ(p.counters().skipped_bytes, 0);
}

TEST(XsensProtocol, CorruptedMessagesAreCountedAndDroppedAndTheNextOneKept) {
  std::vector<uint8_t> stream = {0x00, 0x13, 0xFA, 0x37};  // noise, with a lone preamble
  append(stream, encode_xsens_mtdata2(sample(0)));
  std::vector<uint8_t> bad = encode_xsens_mtdata2(sample(1));
  bad[20] ^= 0x40;  // a flipped bit in the acceleration
  append(stream, bad);
  append(stream, encode_xsens_mtdata2(sample(2)));
  std::vector<uint8_t> short_checksum = encode_xsens_mtdata2(sample(3));
  short_checksum.back() ^= 0x01;
  append(stream, short_checksum);
  append(stream, encode_xsens_mtdata2(sample(4)));
  XsensParser p;
  const auto out = parse(p, stream);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].packet_counter, 0);
  EXPECT_EQ(out[1].packet_counter, 2);
  EXPECT_EQ(out[2].packet_counter, 4);
  EXPECT_EQ(p.counters().bad_checksum, 2);
  EXPECT_NE(p.last_error().find("checksum"), std::string::npos);
  EXPECT_GT(p.counters().skipped_bytes, 4);  // the noise and the bad messages' bytes
}

// A message with a valid checksum: FA FF MID LEN [ext] DATA CS.
std::vector<uint8_t> message(uint8_t mid, const std::vector<uint8_t>& data, bool extended = false) {
  std::vector<uint8_t> m = {0xFA, 0xFF, mid};
  if (extended) {
    m.push_back(0xFF);
    m.push_back(static_cast<uint8_t>(data.size() >> 8));
    m.push_back(static_cast<uint8_t>(data.size() & 0xFF));
  } else {
    m.push_back(static_cast<uint8_t>(data.size()));
  }
  append(m, data);
  uint8_t sum = 0;
  for (size_t i = 1; i < m.size(); ++i) sum = static_cast<uint8_t>(sum + m[i]);
  m.push_back(static_cast<uint8_t>(-sum));
  return m;
}

TEST(XsensProtocol, OtherMessagesExtendedLengthsAndBadContentAreHandled) {
  std::vector<uint8_t> stream;
  append(stream, message(0x3E, {}));                                     // wake-up: other
  append(stream, message(0x0D, std::vector<uint8_t>(300, 0x11), true));  // extended: other
  append(stream, message(0x36, {0x10, 0x20, 0x02, 0x00, 0x07}));         // no time/acc/gyro
  append(stream, message(0x36, {0x40, 0x20, 0x0C, 0x00}));               // packet overruns
  append(stream, {0xFA, 0xFF, 0x36, 0xFF, 0x7F, 0xFF});                  // 32767 bytes: absurd
  append(stream, encode_xsens_mtdata2(sample(9)));
  XsensParser p;
  const auto out = parse(p, stream);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].packet_counter, 9);
  EXPECT_EQ(p.counters().other_messages, 2);
  EXPECT_EQ(p.counters().incomplete, 1);
  EXPECT_EQ(p.counters().malformed, 2);
}

TEST(XsensProtocol, AChecksumByteEqualToThePreambleDoesNotConfuseTheNextMessage) {
  // Find a sample whose checksum byte is 0xFA, then follow it by a normal one, fed in two parts.
  for (int i = 0; i < 5000; ++i) {
    XsensSample s = sample(i);
    const std::vector<uint8_t> a = encode_xsens_mtdata2(s);
    if (a.back() != 0xFA) continue;
    const std::vector<uint8_t> b = encode_xsens_mtdata2(sample(i + 1));
    XsensParser p;
    std::vector<XsensSample> out;
    p.feed(a.data(), a.size(), &out);
    p.feed(b.data(), b.size(), &out);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(p.counters().skipped_bytes, 0);
    return;
  }
  FAIL() << "no sample with checksum 0xFA found";
}

}  // namespace
}  // namespace hs
