#include "common/lcm/convert.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <unordered_set>

#include "common/core/error.h"

namespace hs {
namespace {

constexpr int kMaxImageSide = 1 << 15;  // sanity bound: keeps stride * height far from overflow

hsslam::image_t image_to_msg(const cv::Mat& image, ImageEncoding encoding) {
  if (image.empty() || image.type() != CV_8UC1)
    throw std::invalid_argument("frame_to_msg: images must be non-empty CV_8UC1");
  hsslam::image_t msg;
  msg.width = image.cols;
  msg.height = image.rows;
  msg.exposure_ns = 0;
  if (encoding == ImageEncoding::kPng) {
    msg.encoding = hsslam::image_t::PNG;
    msg.stride = 0;
    if (!cv::imencode(".png", image, msg.data))
      throw std::runtime_error("frame_to_msg: PNG encoding failed");
  } else {
    msg.encoding = hsslam::image_t::MONO8;
    msg.stride = image.cols;
    msg.data.resize(static_cast<size_t>(image.cols) * image.rows);
    for (int r = 0; r < image.rows; ++r)  // rows may be padded in `image` (ROI)
      std::copy(image.ptr<uint8_t>(r), image.ptr<uint8_t>(r) + image.cols,
                msg.data.begin() + static_cast<ptrdiff_t>(r) * image.cols);
  }
  msg.size = static_cast<int32_t>(msg.data.size());
  return msg;
}

cv::Mat image_from_msg(const hsslam::image_t& msg, const std::string& where) {
  const auto fail = [&](const std::string& what) { throw InputError(where, what); };
  if (msg.width <= 0 || msg.height <= 0 || msg.width > kMaxImageSide || msg.height > kMaxImageSide)
    fail("invalid size " + std::to_string(msg.width) + "x" + std::to_string(msg.height));
  if (msg.size < 0 || static_cast<size_t>(msg.size) != msg.data.size())
    fail("size field " + std::to_string(msg.size) + " but " + std::to_string(msg.data.size()) +
         " data bytes");
  if (msg.encoding == hsslam::image_t::MONO8) {
    if (msg.stride < msg.width)
      fail("stride " + std::to_string(msg.stride) + " < width " + std::to_string(msg.width));
    const int64_t expected = static_cast<int64_t>(msg.stride) * msg.height;
    if (msg.size != expected)
      fail("MONO8 data is " + std::to_string(msg.size) +
           " bytes, expected stride*height = " + std::to_string(expected));
    // Wrap the message rows (with their stride) and copy out a packed image.
    const cv::Mat rows(msg.height, msg.width, CV_8UC1, const_cast<uint8_t*>(msg.data.data()),
                       static_cast<size_t>(msg.stride));
    return rows.clone();
  }
  if (msg.encoding == hsslam::image_t::PNG) {
    if (msg.stride != 0)
      fail("PNG image with stride " + std::to_string(msg.stride) + " (must be 0)");
    const cv::Mat image = cv::imdecode(msg.data, cv::IMREAD_UNCHANGED);
    if (image.empty()) fail("PNG data does not decode");
    if (image.type() != CV_8UC1) fail("PNG is not 8-bit mono");
    if (image.cols != msg.width || image.rows != msg.height)
      fail("PNG decodes to " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
           ", declared " + std::to_string(msg.width) + "x" + std::to_string(msg.height));
    return image;
  }
  fail("unknown encoding " + std::to_string(msg.encoding));
  return {};
}

void check_finite(const double* v, int n, const std::string& source, const std::string& field) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(v[i]))
      throw InputError(source, field + "[" + std::to_string(i) + "] is not finite");
}

Eigen::Quaterniond quaternion_from_wxyz(const double* q, const std::string& source) {
  check_finite(q, 4, source, "q_w_b");
  const Eigen::Quaterniond out(q[0], q[1], q[2], q[3]);
  if (std::abs(out.norm() - 1.0) > 1e-3)
    throw InputError(source,
                     "q_w_b is not a unit quaternion (norm " + std::to_string(out.norm()) + ")");
  return out.normalized();
}

void copy3(const Eigen::Vector3d& v, double* out) {
  out[0] = v.x(), out[1] = v.y(), out[2] = v.z();
}

void copy_wxyz(const Eigen::Quaterniond& q, double* out) {
  out[0] = q.w(), out[1] = q.x(), out[2] = q.y(), out[3] = q.z();
}

// Fills the NavState fields shared by ground_truth_t and odometry_t.
template <class Msg>
NavState nav_state_from(const Msg& msg, const std::string& source) {
  check_finite(msg.p_w_b, 3, source, "p_w_b");
  check_finite(msg.v_w, 3, source, "v_w");
  check_finite(msg.gyro_bias, 3, source, "gyro_bias");
  check_finite(msg.accel_bias, 3, source, "accel_bias");
  NavState x;
  x.t_ns = msg.t_ns;
  x.p_w_b = Eigen::Map<const Eigen::Vector3d>(msg.p_w_b);
  x.q_w_b = quaternion_from_wxyz(msg.q_w_b, source);
  x.v_w = Eigen::Map<const Eigen::Vector3d>(msg.v_w);
  x.gyro_bias = Eigen::Map<const Eigen::Vector3d>(msg.gyro_bias);
  x.accel_bias = Eigen::Map<const Eigen::Vector3d>(msg.accel_bias);
  return x;
}

template <class Msg>
void nav_state_to(const NavState& x, Msg& msg) {
  msg.t_ns = x.t_ns;
  copy3(x.p_w_b, msg.p_w_b);
  copy_wxyz(x.q_w_b, msg.q_w_b);
  copy3(x.v_w, msg.v_w);
  copy3(x.gyro_bias, msg.gyro_bias);
  copy3(x.accel_bias, msg.accel_bias);
}

}  // namespace

ImageEncoding parse_image_encoding(const std::string& name) {
  if (name == "mono8") return ImageEncoding::kMono8;
  if (name == "png") return ImageEncoding::kPng;
  throw InputError("image encoding '" + name + "': expected mono8 or png");
}

hsslam::stereo_frame_t frame_to_msg(const StereoFrame& frame, ImageEncoding encoding) {
  hsslam::stereo_frame_t msg;
  msg.t_ns = frame.t_ns;
  msg.seq = frame.seq;
  msg.images.push_back(image_to_msg(frame.cam0, encoding));
  if (frame.stereo()) msg.images.push_back(image_to_msg(frame.cam1, encoding));
  msg.num_images = static_cast<int8_t>(msg.images.size());
  return msg;
}

StereoFrame frame_from_msg(const hsslam::stereo_frame_t& msg, const std::string& source) {
  if (msg.num_images < 1 || msg.num_images > 2 ||
      static_cast<size_t>(msg.num_images) != msg.images.size())
    throw InputError(source, "stereo_frame_t with num_images " + std::to_string(msg.num_images) +
                                 " and " + std::to_string(msg.images.size()) +
                                 " images (expected 1 or 2)");
  StereoFrame frame;
  frame.t_ns = msg.t_ns;
  frame.seq = msg.seq;
  frame.cam0 = image_from_msg(msg.images[0], source + ": image 0");
  if (msg.num_images == 2) {
    frame.cam1 = image_from_msg(msg.images[1], source + ": image 1");
    if (frame.cam1.size() != frame.cam0.size())
      throw InputError(source, "cam0 and cam1 images differ in size");
  }
  return frame;
}

hsslam::imu_batch_t imu_batch_to_msg(const std::vector<ImuSample>& samples, int64_t seq) {
  if (samples.empty()) throw std::invalid_argument("imu_batch_to_msg: empty batch");
  hsslam::imu_batch_t msg;
  msg.t_ns = samples.back().t_ns;
  msg.seq = seq;
  msg.num_samples = static_cast<int32_t>(samples.size());
  msg.samples.resize(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) {
    msg.samples[i].t_ns = samples[i].t_ns;
    copy3(samples[i].gyro, msg.samples[i].gyro);
    copy3(samples[i].accel, msg.samples[i].accel);
  }
  return msg;
}

std::vector<ImuSample> imu_batch_from_msg(const hsslam::imu_batch_t& msg,
                                          const std::string& source) {
  if (msg.num_samples < 1 || static_cast<size_t>(msg.num_samples) != msg.samples.size())
    throw InputError(source, "imu_batch_t with num_samples " + std::to_string(msg.num_samples) +
                                 " and " + std::to_string(msg.samples.size()) + " samples");
  std::vector<ImuSample> samples(msg.samples.size());
  for (size_t i = 0; i < samples.size(); ++i) {
    const hsslam::imu_sample_t& m = msg.samples[i];
    const std::string where = "sample " + std::to_string(i);
    check_finite(m.gyro, 3, source, where + " gyro");
    check_finite(m.accel, 3, source, where + " accel");
    if (i > 0 && m.t_ns <= samples[i - 1].t_ns)
      throw InputError(source, where + ": time " + std::to_string(m.t_ns) + " does not increase");
    samples[i].t_ns = m.t_ns;
    samples[i].gyro = Eigen::Map<const Eigen::Vector3d>(m.gyro);
    samples[i].accel = Eigen::Map<const Eigen::Vector3d>(m.accel);
  }
  if (msg.t_ns != samples.back().t_ns)
    throw InputError(source, "imu_batch_t t_ns " + std::to_string(msg.t_ns) +
                                 " differs from the last sample's " +
                                 std::to_string(samples.back().t_ns));
  return samples;
}

hsslam::ground_truth_t ground_truth_to_msg(const NavState& x) {
  hsslam::ground_truth_t msg;
  nav_state_to(x, msg);
  return msg;
}

NavState ground_truth_from_msg(const hsslam::ground_truth_t& msg, const std::string& source) {
  return nav_state_from(msg, source);
}

hsslam::odometry_t odometry_to_msg(const NavState& x, int64_t seq, int32_t map_id, int8_t state,
                                   float quality) {
  hsslam::odometry_t msg{};
  nav_state_to(x, msg);
  msg.seq = seq;
  msg.map_id = map_id;
  msg.state = state;
  msg.quality = quality;
  return msg;
}

NavState odometry_from_msg(const hsslam::odometry_t& msg, const std::string& source) {
  if (msg.state < hsslam::odometry_t::INITIALISING || msg.state > hsslam::odometry_t::RELOCALISED)
    throw InputError(source, "odometry_t with unknown state " + std::to_string(msg.state));
  if (!(msg.quality >= 0.0f && msg.quality <= 1.0f))
    throw InputError(source,
                     "odometry_t quality " + std::to_string(msg.quality) + " outside [0, 1]");
  check_finite(msg.covariance, 36, source, "covariance");
  return nav_state_from(msg, source);
}

hsslam::keyframe_pose_t keyframe_pose_to_msg(int64_t id, const NavState& x) {
  hsslam::keyframe_pose_t msg;
  nav_state_to(x, msg);
  msg.id = id;
  return msg;
}

NavState keyframe_pose_from_msg(const hsslam::keyframe_pose_t& msg, const std::string& source) {
  if (msg.id < 0) throw InputError(source, "keyframe id " + std::to_string(msg.id));
  return nav_state_from(msg, source);
}

hsslam::map_update_t map_update_to_msg(const MapCorrection& c) {
  hsslam::map_update_t msg{};
  msg.t_ns = c.t_ns;
  msg.seq = c.seq;
  msg.map_id = c.map_id;
  msg.previous_map_id = c.map_id;
  msg.kind = hsslam::map_update_t::LOCAL_BA;
  copy_wxyz(Eigen::Quaterniond::Identity(), msg.q_new_old);
  for (const KeyframeCorrection& k : c.keyframes)
    msg.keyframes.push_back(keyframe_pose_to_msg(k.id, k.state));
  for (const PointCorrection& p : c.points) {
    hsslam::map_point_t m;
    m.id = p.id;
    copy3(p.p_w, m.p_w);
    msg.points.push_back(m);
  }
  msg.removed_point_ids = c.removed_points;
  copy3(c.g_w, msg.g_w);
  msg.num_keyframes = static_cast<int32_t>(msg.keyframes.size());
  msg.num_points = static_cast<int32_t>(msg.points.size());
  msg.num_removed_points = static_cast<int32_t>(msg.removed_point_ids.size());
  return msg;
}

MapCorrection map_correction_from_msg(const hsslam::map_update_t& msg, const std::string& source) {
  const std::string where = source + ": map_update_t seq " + std::to_string(msg.seq);
  const auto fail = [&](const std::string& what) { throw InputError(where, what); };
  if (msg.kind != hsslam::map_update_t::LOCAL_BA)
    fail(std::string("kind ") +
         (msg.kind == hsslam::map_update_t::LOOP    ? "LOOP"
          : msg.kind == hsslam::map_update_t::MERGE ? "MERGE"
          : msg.kind == hsslam::map_update_t::FULL_BA
              ? "FULL_BA"
              : "unknown (" + std::to_string(msg.kind) + ")") +
         " is not supported by this tracker");
  const auto check_count = [&](int32_t n, size_t size, const char* name) {
    if (n < 0 || static_cast<size_t>(n) != size)
      fail(std::string(name) + " " + std::to_string(n) + " but " + std::to_string(size) +
           " entries");
  };
  check_count(msg.num_keyframes, msg.keyframes.size(), "num_keyframes");
  check_count(msg.num_points, msg.points.size(), "num_points");
  check_count(msg.num_removed_points, msg.removed_point_ids.size(), "num_removed_points");
  std::unordered_set<int64_t> seen;
  const auto check_id = [&](int64_t id, const char* what) {
    if (id < 0 || !seen.insert(id).second)
      fail(std::string(what) + " id " + std::to_string(id) + (id < 0 ? " negative" : " twice"));
  };
  check_finite(msg.g_w, 3, where, "g_w");
  MapCorrection c;
  c.g_w = Eigen::Map<const Eigen::Vector3d>(msg.g_w);
  c.seq = msg.seq;
  c.map_id = msg.map_id;
  c.t_ns = msg.t_ns;
  for (const hsslam::keyframe_pose_t& k : msg.keyframes) {
    check_id(k.id, "keyframe");
    c.keyframes.push_back({k.id, keyframe_pose_from_msg(k, where + ": keyframe")});
  }
  seen.clear();
  for (const hsslam::map_point_t& p : msg.points) {
    check_id(p.id, "point");
    check_finite(p.p_w, 3, where, "point " + std::to_string(p.id) + " p_w");
    c.points.push_back({p.id, Eigen::Map<const Eigen::Vector3d>(p.p_w)});
  }
  seen.clear();
  for (int64_t id : msg.removed_point_ids) check_id(id, "removed point");
  c.removed_points = msg.removed_point_ids;
  return c;
}

hsslam::reloc_answer_t reloc_answer_to_msg(const RelocAnswer& a) {
  hsslam::reloc_answer_t msg{};
  msg.t_ns = a.t_ns;
  msg.seq = a.seq;
  msg.found = a.found;
  msg.map_id = a.map_id;
  NavState x;
  x.t_ns = a.t_ns;
  x.q_w_b = Eigen::Quaterniond(a.T_w_b.linear());
  x.p_w_b = a.T_w_b.translation();
  msg.pose = keyframe_pose_to_msg(std::max<int64_t>(a.keyframe_id, 0), x);
  msg.inliers = a.inliers;
  msg.message = a.message;
  return msg;
}

RelocAnswer reloc_answer_from_msg(const hsslam::reloc_answer_t& msg, const std::string& source) {
  const std::string where = source + ": reloc_answer_t seq " + std::to_string(msg.seq);
  RelocAnswer a;
  a.seq = msg.seq;
  a.t_ns = msg.t_ns;
  a.found = msg.found;
  a.message = msg.message;
  if (!a.found) return a;
  if (msg.map_id < 0) throw InputError(where, "map id " + std::to_string(msg.map_id));
  if (msg.inliers < 0) throw InputError(where, "inliers " + std::to_string(msg.inliers));
  const NavState x = keyframe_pose_from_msg(msg.pose, where + ": pose");
  a.map_id = msg.map_id;
  a.keyframe_id = msg.pose.id;
  a.T_w_b = x.T_w_b();
  a.inliers = msg.inliers;
  return a;
}

}  // namespace hs
