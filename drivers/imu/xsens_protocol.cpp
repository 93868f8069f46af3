#include "drivers/imu/xsens_protocol.h"

#include <cstdio>
#include <cstring>

namespace hs {
namespace {

constexpr uint8_t kPreamble = 0xFA, kBusId = 0xFF, kMtData2 = 0x36;
constexpr uint16_t kPacketCounter = 0x1020, kSampleTimeFine = 0x1060, kAcceleration = 0x4020,
                   kRateOfTurn = 0x8020;
constexpr size_t kMaxLength = 2048;  // the protocol's largest (extended) message

uint32_t be32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | p[3];
}

float be_float(const uint8_t* p) {
  const uint32_t bits = be32(p);
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

Eigen::Vector3d be_vec3(const uint8_t* p) {
  return Eigen::Vector3d(be_float(p), be_float(p + 4), be_float(p + 8));
}

void put_be(uint64_t v, int bytes, std::vector<uint8_t>* out) {
  for (int i = bytes - 1; i >= 0; --i) out->push_back(static_cast<uint8_t>(v >> (8 * i)));
}

void put_vec3(const Eigen::Vector3d& v, std::vector<uint8_t>* out) {
  for (int i = 0; i < 3; ++i) {
    const float f = static_cast<float>(v[i]);
    uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    put_be(bits, 4, out);
  }
}

}  // namespace

void XsensParser::feed(const uint8_t* data, size_t size, std::vector<XsensSample>* out) {
  buffer_.insert(buffer_.end(), data, data + size);
  size_t pos = 0;
  while (true) {
    // The next preamble + bus id.
    size_t start = pos;
    while (start + 1 < buffer_.size() &&
           !(buffer_[start] == kPreamble && buffer_[start + 1] == kBusId))
      ++start;
    if (start + 1 >= buffer_.size()) {  // keep a trailing preamble byte for the next feed
      const size_t keep = pos < buffer_.size() && buffer_.back() == kPreamble ? 1 : 0;
      counters_.skipped_bytes += static_cast<int64_t>(buffer_.size() - keep - pos);
      pos = buffer_.size() - keep;
      break;
    }
    counters_.skipped_bytes += static_cast<int64_t>(start - pos);
    pos = start;
    if (buffer_.size() - pos < 4) break;  // header incomplete
    size_t length = buffer_[pos + 3];
    size_t header = 4;
    if (length == 0xFF) {
      if (buffer_.size() - pos < 6) break;
      length = (size_t{buffer_[pos + 4]} << 8) | buffer_[pos + 5];
      header = 6;
    }
    if (length > kMaxLength) {
      ++counters_.malformed;
      last_error_ = "message length " + std::to_string(length) + " > " + std::to_string(kMaxLength);
      pos += 1;  // not a message: look for the next preamble
      continue;
    }
    const size_t total = header + length + 1;
    if (buffer_.size() - pos < total) break;  // wait for the rest
    uint8_t sum = 0;
    for (size_t i = pos + 1; i < pos + total; ++i) sum = static_cast<uint8_t>(sum + buffer_[i]);
    if (sum != 0) {
      ++counters_.bad_checksum;
      last_error_ = "checksum mismatch in a message of " + std::to_string(total) + " bytes";
      pos += 1;
      continue;
    }
    if (buffer_[pos + 2] == kMtData2)
      parse_mtdata2(buffer_.data() + pos + header, length, out);
    else
      ++counters_.other_messages;
    pos += total;
  }
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(pos));
}

void XsensParser::parse_mtdata2(const uint8_t* data, size_t size, std::vector<XsensSample>* out) {
  XsensSample s;
  bool has_time = false, has_accel = false, has_gyro = false;
  size_t i = 0;
  while (i < size) {
    if (size - i < 3) {
      ++counters_.malformed;
      last_error_ = "MTData2: a data packet header overruns the message";
      return;
    }
    const uint16_t xdi = static_cast<uint16_t>((data[i] << 8) | data[i + 1]);
    const size_t n = data[i + 2];
    const uint8_t* v = data + i + 3;
    if (size - i - 3 < n) {
      ++counters_.malformed;
      char what[64];
      std::snprintf(what, sizeof what, "MTData2: data packet 0x%04X overruns the message", xdi);
      last_error_ = what;
      return;
    }
    if (xdi == kPacketCounter && n == 2) {
      s.packet_counter = static_cast<uint16_t>((v[0] << 8) | v[1]);
    } else if (xdi == kSampleTimeFine && n == 4) {
      s.sample_time_fine = be32(v);
      has_time = true;
    } else if (xdi == kAcceleration && n == 12) {
      s.accel = be_vec3(v);
      has_accel = true;
    } else if (xdi == kRateOfTurn && n == 12) {
      s.gyro = be_vec3(v);
      has_gyro = true;
    }
    i += 3 + n;
  }
  if (!has_time || !has_accel || !has_gyro || !s.accel.allFinite() || !s.gyro.allFinite()) {
    ++counters_.incomplete;
    last_error_ =
        "MTData2 without SampleTimeFine, Acceleration and RateOfTurn (float32), or "
        "not finite: configure the device's output";
    return;
  }
  ++counters_.samples;
  out->push_back(s);
}

std::vector<uint8_t> encode_xsens_mtdata2(const XsensSample& s) {
  std::vector<uint8_t> payload;
  put_be(kPacketCounter, 2, &payload);
  payload.push_back(2);
  put_be(s.packet_counter, 2, &payload);
  put_be(kSampleTimeFine, 2, &payload);
  payload.push_back(4);
  put_be(s.sample_time_fine, 4, &payload);
  put_be(kAcceleration, 2, &payload);
  payload.push_back(12);
  put_vec3(s.accel, &payload);
  put_be(kRateOfTurn, 2, &payload);
  payload.push_back(12);
  put_vec3(s.gyro, &payload);
  std::vector<uint8_t> msg;
  msg.reserve(payload.size() + 5);
  for (const uint8_t b : {kPreamble, kBusId, kMtData2, static_cast<uint8_t>(payload.size())})
    msg.push_back(b);
  for (const uint8_t b : payload) msg.push_back(b);
  uint8_t sum = 0;
  for (size_t i = 1; i < msg.size(); ++i) sum = static_cast<uint8_t>(sum + msg[i]);
  msg.push_back(static_cast<uint8_t>(-sum));
  return msg;
}

}  // namespace hs
