#include "mapper/map_file.h"

#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <type_traits>

#include "common/core/atomic_file.h"
#include "common/core/error.h"

namespace hs {
namespace {

constexpr char kMagic[8] = {'H', 'S', 'S', 'L', 'A', 'M', 'A', 'P'};
constexpr size_t kHeaderBytes = 8 + 4 + 8 + 4;

class Writer {
 public:
  template <typename T>
  void put(const T& v) {
    static_assert(std::is_arithmetic_v<T>);
    const auto* b = reinterpret_cast<const char*>(&v);
    bytes.insert(bytes.end(), b, b + sizeof(T));
  }
  template <typename Derived>
  void put_vec(const Eigen::MatrixBase<Derived>& v) {
    for (Eigen::Index i = 0; i < v.size(); ++i) put(static_cast<double>(v(i)));
  }
  void put_pose(const Eigen::Isometry3d& T) {
    put_vec(Eigen::Quaterniond(T.linear()).coeffs());
    put_vec(T.translation());
  }
  void put_state(const NavState& s) {
    put(s.t_ns);
    put_vec(s.p_w_b);
    put_vec(s.q_w_b.coeffs());
    put_vec(s.v_w);
    put_vec(s.gyro_bias);
    put_vec(s.accel_bias);
  }
  std::string bytes;
};

// Reads the payload; every read is bounds-checked and every value checked for what it can be.
class Reader {
 public:
  Reader(const std::string& path, const std::string& bytes) : path_(path), bytes_(bytes) {}
  template <typename T>
  T get() {
    static_assert(std::is_arithmetic_v<T>);
    need(sizeof(T));
    T v;
    std::memcpy(&v, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    if constexpr (std::is_floating_point_v<T>)
      if (!std::isfinite(v)) fail("a non-finite number");
    return v;
  }
  Eigen::Vector3d vec3() {
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) v(i) = get<double>();
    return v;
  }
  Eigen::Quaterniond quat() {
    Eigen::Quaterniond q;
    // One read per statement: argument evaluation order is unspecified.
    for (int i = 0; i < 4; ++i) q.coeffs()(i) = get<double>();
    if (std::abs(q.norm() - 1.0) > 1e-6) fail("a rotation that is not a unit quaternion");
    return q;
  }
  Eigen::Isometry3d pose() {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = quat().toRotationMatrix();
    T.translation() = vec3();
    return T;
  }
  NavState state() {
    NavState s;
    s.t_ns = get<int64_t>();
    s.p_w_b = vec3();
    s.q_w_b = quat();
    s.v_w = vec3();
    s.gyro_bias = vec3();
    s.accel_bias = vec3();
    return s;
  }
  // A count of items of at least `min_item_bytes` each: no more than the bytes left can hold.
  size_t count(size_t min_item_bytes) {
    const uint64_t n = get<uint64_t>();
    if (n > (bytes_.size() - at_) / min_item_bytes) fail("a count of " + std::to_string(n));
    return static_cast<size_t>(n);
  }
  void bytes(uint8_t* out, size_t n) {
    need(n);
    std::memcpy(out, bytes_.data() + at_, n);
    at_ += n;
  }
  bool done() const { return at_ == bytes_.size(); }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_, "corrupt map: " + what + " at payload byte " + std::to_string(at_));
  }

 private:
  void need(size_t n) const {
    if (bytes_.size() - at_ < n) fail("it ends early");
  }
  const std::string& path_;
  const std::string& bytes_;
  size_t at_ = 0;
};

void write_keyframe(Writer& w, const MapperKeyframe& kf) {
  w.put(kf.id);
  w.put(kf.map_id);
  w.put(kf.prev_id);
  w.put_state(kf.state);
  w.put(static_cast<uint64_t>(kf.keypoints.size()));
  for (size_t i = 0; i < kf.keypoints.size(); ++i) {
    const MapperKeypoint& k = kf.keypoints[i];
    for (float f : {k.u, k.v, k.u_right, k.v_right, k.depth, k.angle}) w.put(f);
    w.put(static_cast<int32_t>(k.octave));
    w.put(k.point_id);
    w.put(static_cast<uint8_t>(k.detected));
    w.bytes.append(reinterpret_cast<const char*>(kf.descriptors[i].data()), 32);
  }
  w.put(static_cast<uint64_t>(kf.point_positions.size()));
  for (const auto& [id, p_w] : kf.point_positions) {
    w.put(id);
    w.put_vec(p_w);
  }
  w.put(static_cast<uint64_t>(kf.imu.size()));
  for (const ImuSample& s : kf.imu) {
    w.put(s.t_ns);
    w.put_vec(s.gyro);
    w.put_vec(s.accel);
  }
}

MapperKeyframe read_keyframe(Reader& r) {
  MapperKeyframe kf;
  kf.id = r.get<int64_t>();
  kf.map_id = r.get<int32_t>();
  kf.prev_id = r.get<int64_t>();
  kf.state = r.state();
  if (kf.id < 0 || kf.prev_id < -1 || kf.prev_id >= kf.id) r.fail("keyframe ids");
  const size_t n = r.count(6 * 4 + 4 + 8 + 1 + 32);
  kf.keypoints.resize(n);
  kf.descriptors.resize(n);
  for (size_t i = 0; i < n; ++i) {
    MapperKeypoint& k = kf.keypoints[i];
    for (float* f : {&k.u, &k.v, &k.u_right, &k.v_right, &k.depth, &k.angle}) *f = r.get<float>();
    k.octave = r.get<int32_t>();
    k.point_id = r.get<int64_t>();
    const auto detected = r.get<uint8_t>();
    if (k.octave < 0 || k.point_id < -1 || detected > 1)
      r.fail("a keypoint of keyframe " + std::to_string(kf.id));
    k.detected = detected == 1;
    r.bytes(kf.descriptors[i].data(), 32);
  }
  const size_t points = r.count(8 + 3 * 8);
  for (size_t i = 0; i < points; ++i) {
    const auto id = r.get<int64_t>();
    kf.point_positions[id] = r.vec3();
  }
  for (const MapperKeypoint& k : kf.keypoints)
    if (k.point_id >= 0 && !kf.point_positions.count(k.point_id))
      r.fail("keyframe " + std::to_string(kf.id) + " observes a point without a position");
  const size_t samples = r.count(8 + 6 * 8);
  for (size_t i = 0; i < samples; ++i) {
    ImuSample s;
    s.t_ns = r.get<int64_t>();
    s.gyro = r.vec3();
    s.accel = r.vec3();
    if (!kf.imu.empty() && s.t_ns <= kf.imu.back().t_ns) r.fail("IMU samples out of order");
    kf.imu.push_back(s);
  }
  return kf;
}

}  // namespace

uint32_t crc32(const uint8_t* data, size_t size) {
  static const std::array<uint32_t, 256> table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  uint32_t c = 0xFFFFFFFFu;
  for (size_t i = 0; i < size; ++i) c = table[(c ^ data[i]) & 0xFF] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

void write_map_file(const std::string& path, const MapFile& map) {
  Writer payload;
  payload.put_vec(map.g_w);
  payload.put(static_cast<uint64_t>(map.keyframes.size()));
  for (const MapperKeyframe& kf : map.keyframes) write_keyframe(payload, kf);
  payload.put(static_cast<uint64_t>(map.loops.size()));
  for (const LoopFound& l : map.loops) {
    for (int64_t v : {l.query, l.candidate, l.query_t_ns, l.candidate_t_ns}) payload.put(v);
    payload.put_pose(l.T_c_q);
    payload.put_pose(l.drift);
    payload.put(static_cast<int32_t>(l.inliers));
    payload.put(l.path_m);
  }
  Writer file;
  file.bytes.append(kMagic, sizeof(kMagic));
  file.put(kMapFileVersion);
  file.put(static_cast<uint64_t>(payload.bytes.size()));
  file.put(crc32(reinterpret_cast<const uint8_t*>(payload.bytes.data()), payload.bytes.size()));
  file.bytes += payload.bytes;
  write_file_atomically(path, file.bytes);
}

MapFile read_map_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open the map file");
  const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (all.size() < kHeaderBytes || std::memcmp(all.data(), kMagic, sizeof(kMagic)) != 0)
    throw InputError(path, "not an HS-SLAM map file");
  uint32_t version = 0, crc = 0;
  uint64_t size = 0;
  std::memcpy(&version, all.data() + 8, 4);
  std::memcpy(&size, all.data() + 12, 8);
  std::memcpy(&crc, all.data() + 20, 4);
  if (version != kMapFileVersion)
    throw InputError(path, "map file version " + std::to_string(version) +
                               "; this build reads version " + std::to_string(kMapFileVersion));
  if (all.size() - kHeaderBytes != size)
    throw InputError(path, "truncated map file: " + std::to_string(all.size() - kHeaderBytes) +
                               " of " + std::to_string(size) + " payload bytes");
  const std::string payload = all.substr(kHeaderBytes);
  if (crc32(reinterpret_cast<const uint8_t*>(payload.data()), payload.size()) != crc)
    throw InputError(path, "corrupt map file: checksum mismatch");

  Reader r(path, payload);
  MapFile map;
  map.g_w = r.vec3();
  const size_t keyframes = r.count(8 + 4 + 8 + 8 + 16 * 8 + 3 * 8);
  for (size_t i = 0; i < keyframes; ++i) {
    map.keyframes.push_back(read_keyframe(r));
    if (i > 0 && map.keyframes[i].id <= map.keyframes[i - 1].id) r.fail("keyframes out of order");
  }
  const size_t loops = r.count(4 * 8 + 14 * 8 + 4 + 8);
  for (size_t i = 0; i < loops; ++i) {
    LoopFound l;
    for (int64_t* v : {&l.query, &l.candidate, &l.query_t_ns, &l.candidate_t_ns})
      *v = r.get<int64_t>();
    l.T_c_q = r.pose();
    l.drift = r.pose();
    l.inliers = r.get<int32_t>();
    l.path_m = r.get<double>();
    map.loops.push_back(l);
  }
  if (!r.done()) r.fail("bytes after the last loop");
  return map;
}

}  // namespace hs
