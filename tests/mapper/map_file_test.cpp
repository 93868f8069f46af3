// The map file: a round trip keeps every field; a file that is not a map, of another version,
// truncated, corrupt, or well formed but holding impossible values is refused with the reason;
// a mapper started from a map holds it as a world of its own.
#include "mapper/map_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/core/error.h"
#include "mapper/mapper.h"
#include "tests/common/temp_dir.h"

namespace hs {
namespace {

MapperKeyframe keyframe(int64_t id, int64_t prev) {
  MapperKeyframe kf;
  kf.id = id;
  kf.map_id = 3;
  kf.prev_id = prev;
  kf.state.t_ns = 1'000'000'000 * (id + 1);
  kf.state.p_w_b = Eigen::Vector3d(id, 0.5, 1.5);
  kf.state.q_w_b = Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * id, Eigen::Vector3d::UnitZ()));
  kf.state.v_w = Eigen::Vector3d(1, 0, 0);
  kf.state.accel_bias = Eigen::Vector3d(0.01, -0.02, 0.03);
  for (int k = 0; k < 3; ++k) {
    MapperKeypoint kp;
    kp.u = 100.25f + k;
    kp.v = 50.5f;
    kp.depth = k == 0 ? 3.5f : -1.f;
    kp.octave = k;
    kp.angle = 12.5f;
    kp.point_id = k < 2 ? 10 + k : -1;
    kp.detected = k > 0;
    kf.keypoints.push_back(kp);
    Descriptor d{};
    d.fill(static_cast<uint8_t>(id * 7 + k));
    kf.descriptors.push_back(d);
  }
  kf.point_positions[10] = Eigen::Vector3d(4, 1, 1);
  kf.point_positions[11] = Eigen::Vector3d(5, -1, 2);
  kf.imu.push_back(
      {kf.state.t_ns - 5'000'000, Eigen::Vector3d(0, 0, 0.1), Eigen::Vector3d(0, 0, 9.8)});
  return kf;
}

MapFile sample() {
  MapFile m;
  m.g_w = Eigen::Vector3d(0.01, 0, -9.81);
  m.keyframes = {keyframe(0, -1), keyframe(1, 0)};
  LoopFound l;
  l.query = 1;
  l.candidate = 0;
  l.query_t_ns = 2'000'000'000;
  l.candidate_t_ns = 1'000'000'000;
  l.T_c_q.translation() = Eigen::Vector3d(1, 0.1, 0);
  l.inliers = 77;
  l.path_m = 12.5;
  m.loops = {l};
  return m;
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

void expect_refused(const std::string& path, const std::string& what) {
  try {
    read_map_file(path);
    ADD_FAILURE() << "accepted; expected: " << what;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(MapFile, CrcIsZlibs) {
  const std::string s = "123456789";
  EXPECT_EQ(crc32(reinterpret_cast<const uint8_t*>(s.data()), s.size()), 0xCBF43926u);
}

TEST(MapFile, ARoundTripKeepsEveryField) {
  test::TempDir dir;
  const std::string path = dir.path() + "/map.hsmap";
  const MapFile in = sample();
  write_map_file(path, in);
  const MapFile out = read_map_file(path);
  EXPECT_EQ(out.g_w, in.g_w);
  ASSERT_EQ(out.keyframes.size(), 2u);
  for (size_t k = 0; k < 2; ++k) {
    const MapperKeyframe &a = in.keyframes[k], &b = out.keyframes[k];
    EXPECT_EQ(b.id, a.id);
    EXPECT_EQ(b.map_id, a.map_id);
    EXPECT_EQ(b.prev_id, a.prev_id);
    EXPECT_EQ(b.state.t_ns, a.state.t_ns);
    EXPECT_EQ(b.state.p_w_b, a.state.p_w_b);
    EXPECT_EQ(b.state.q_w_b.coeffs(), a.state.q_w_b.coeffs());
    EXPECT_EQ(b.state.accel_bias, a.state.accel_bias);
    ASSERT_EQ(b.keypoints.size(), a.keypoints.size());
    for (size_t i = 0; i < a.keypoints.size(); ++i) {
      EXPECT_EQ(b.keypoints[i].u, a.keypoints[i].u);
      EXPECT_EQ(b.keypoints[i].depth, a.keypoints[i].depth);
      EXPECT_EQ(b.keypoints[i].octave, a.keypoints[i].octave);
      EXPECT_EQ(b.keypoints[i].point_id, a.keypoints[i].point_id);
      EXPECT_EQ(b.keypoints[i].detected, a.keypoints[i].detected);
      EXPECT_EQ(b.descriptors[i], a.descriptors[i]);
    }
    EXPECT_EQ(b.point_positions, a.point_positions);
    ASSERT_EQ(b.imu.size(), 1u);
    EXPECT_EQ(b.imu[0].accel, a.imu[0].accel);
  }
  ASSERT_EQ(out.loops.size(), 1u);
  EXPECT_EQ(out.loops[0].inliers, 77);
  EXPECT_TRUE(out.loops[0].T_c_q.isApprox(in.loops[0].T_c_q));
}

TEST(MapFile, BrokenFilesAreRefusedWithTheReason) {
  test::TempDir dir;
  const std::string good = dir.path() + "/good.hsmap", bad = dir.path() + "/bad.hsmap";
  write_map_file(good, sample());
  const std::string bytes = read_bytes(good);

  write_bytes(bad, "keyframes: []\n");
  expect_refused(bad, "not an HS-SLAM map file");
  expect_refused(dir.path() + "/missing.hsmap", "cannot open");
  write_bytes(bad, bytes.substr(0, bytes.size() - 10));
  expect_refused(bad, "truncated");
  std::string flipped = bytes;
  flipped[flipped.size() / 2] ^= 0x10;
  write_bytes(bad, flipped);
  expect_refused(bad, "checksum");
  std::string version = bytes;
  version[8] = 9;
  write_bytes(bad, version);
  expect_refused(bad, "version 9");

  // Well formed, checksum right, values impossible: each is named.
  MapFile m = sample();
  m.keyframes[1].state.q_w_b.coeffs() *= 2.0;
  write_map_file(bad, m);
  expect_refused(bad, "unit quaternion");
  m = sample();
  m.keyframes[1].point_positions.erase(11);
  write_map_file(bad, m);
  expect_refused(bad, "without a position");
  m = sample();
  std::swap(m.keyframes[0], m.keyframes[1]);
  m.keyframes[1].prev_id = -1;
  write_map_file(bad, m);
  expect_refused(bad, "out of order");
}

TEST(MapFile, AMapperStartsFromASavedMapAsAWorldOfItsOwn) {
  Mapper first(euroc_stereo_calib(), {});
  first.load(sample());
  const MapFile saved = first.map_file();
  ASSERT_EQ(saved.keyframes.size(), 2u);
  // Out of the way of a new tracker's ids, which start from 0 again.
  EXPECT_GE(saved.keyframes[0].id, int64_t{1} << 48);
  EXPECT_EQ(saved.keyframes[1].prev_id, saved.keyframes[0].id);
  EXPECT_EQ(saved.keyframes[1].point_positions.size(), 2u);
  for (const auto& [id, p_w] : saved.keyframes[1].point_positions) {
    EXPECT_GE(id, int64_t{1} << 56);
    EXPECT_EQ(p_w, sample().keyframes[1].point_positions.at(id - (int64_t{1} << 56)));
  }
  EXPECT_EQ(saved.g_w, sample().g_w);
  EXPECT_EQ(saved.loops.at(0).query, saved.keyframes[1].id);
  EXPECT_EQ(first.graph().num_points(), 2u);
  EXPECT_THROW(first.load(sample()), std::logic_error);
}

}  // namespace
}  // namespace hs
