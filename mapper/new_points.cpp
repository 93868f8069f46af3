#include "mapper/new_points.h"

#include <cmath>
#include <limits>
#include <optional>

#include "common/geometry/triangulation.h"
#include "common/imu/so3.h"

namespace hs {
namespace {

struct FreeKeypoint {
  int index;
  Eigen::Vector3d f_c;  // unit bearing in the camera
  Eigen::Vector3d f_w;  // ... in the world
};

struct View {
  const MapperKeyframe* kf;
  Eigen::Isometry3d T_w_c;
  std::vector<FreeKeypoint> free;
};

View view_of(const MapperKeyframe& kf, const CameraCalib& cam) {
  View v{&kf, kf.state.T_w_b() * cam.T_b_c, {}};
  for (size_t i = 0; i < kf.keypoints.size(); ++i) {
    const MapperKeypoint& kp = kf.keypoints[i];
    if (kp.point_id >= 0) continue;
    const Eigen::Vector3d f_c = cam.intrinsics.unproject(Eigen::Vector2d(kp.u, kp.v));
    v.free.push_back({static_cast<int>(i), f_c, v.T_w_c.linear() * f_c});
  }
  return v;
}

class PairTriangulator {
 public:
  PairTriangulator(const View& a, const View& b, const PinholeRadtan& cam, const NewPointOptions& o)
      : a_(a), b_(b), cam_(cam), o_(o) {
    const Eigen::Isometry3d T_b_a = b.T_w_c.inverse() * a.T_w_c;
    E_ = so3::hat(T_b_a.translation()) * T_b_a.linear();  // f_b' E f_a = 0
    min_cos_ = std::cos(o.min_parallax_deg * M_PI / 180.0);
  }

  // The best match of a's free keypoint k among b's unused free keypoints (-1: none).
  int match(const FreeKeypoint& k, const std::vector<bool>& used_b) const {
    Eigen::Vector3d n = E_ * k.f_c;  // the epipolar plane's normal in b
    if (n.norm() < 1e-12) return -1;
    n.normalize();
    int best = -1, best_d = std::numeric_limits<int>::max(), second_d = best_d;
    for (size_t j = 0; j < b_.free.size(); ++j) {
      if (used_b[j]) continue;
      const FreeKeypoint& c = b_.free[j];
      const int octave = b_.kf->keypoints[static_cast<size_t>(c.index)].octave;
      // Distance from the epipolar plane as an angle, against the pixel tolerance as one.
      if (std::abs(c.f_c.dot(n)) > o_.epipolar_px * std::pow(o_.octave_scale, octave) / cam_.fx)
        continue;
      if (c.f_w.dot(k.f_w) > min_cos_) continue;  // too little parallax to place it
      const int d = hamming_distance(a_.kf->descriptors[static_cast<size_t>(k.index)],
                                     b_.kf->descriptors[static_cast<size_t>(c.index)]);
      if (d < best_d) {
        second_d = best_d;
        best_d = d;
        best = static_cast<int>(j);
      } else if (d < second_d) {
        second_d = d;
      }
    }
    if (best < 0 || best_d > o_.max_hamming ||
        (second_d != std::numeric_limits<int>::max() && best_d >= o_.ratio * second_d))
      return -1;
    return best;
  }

  bool triangulate(const FreeKeypoint& ka, const FreeKeypoint& kb, Eigen::Vector3d* p_w) const {
    const std::optional<Eigen::Vector3d> p_a =
        triangulate_two_view(ka.f_c.head<2>() / ka.f_c.z(), kb.f_c.head<2>() / kb.f_c.z(),
                             a_.T_w_c.inverse() * b_.T_w_c);
    if (!p_a) return false;
    *p_w = a_.T_w_c * *p_a;
    const MapperKeypoint& pa = a_.kf->keypoints[static_cast<size_t>(ka.index)];
    const MapperKeypoint& pb = b_.kf->keypoints[static_cast<size_t>(kb.index)];
    if (!reprojects(a_, pa, *p_w) || !reprojects(b_, pb, *p_w)) return false;
    // The keypoints' pyramid levels say how far the point is from each camera relative to the
    // other; a point at odds with them is a wrong match.
    const double dist_a = (*p_w - a_.T_w_c.translation()).norm();
    const double dist_b = (*p_w - b_.T_w_c.translation()).norm();
    const double ratio_dist = dist_a / dist_b;
    const double ratio_octave = std::pow(o_.octave_scale, pa.octave - pb.octave);
    return ratio_dist * o_.scale_ratio_factor >= ratio_octave &&
           ratio_dist <= ratio_octave * o_.scale_ratio_factor;
  }

 private:
  bool reprojects(const View& v, const MapperKeypoint& kp, const Eigen::Vector3d& p_w) const {
    Eigen::Vector2d uv;
    if (!cam_.project(v.T_w_c.inverse() * p_w, &uv)) return false;
    const double tolerance = o_.max_reprojection_px * std::pow(o_.octave_scale, kp.octave);
    return (uv - Eigen::Vector2d(kp.u, kp.v)).squaredNorm() <= tolerance * tolerance;
  }

  const View& a_;
  const View& b_;
  const PinholeRadtan& cam_;
  const NewPointOptions& o_;
  Eigen::Matrix3d E_;
  double min_cos_ = 1.0;
};

}  // namespace

std::vector<NewPoint> triangulate_new_points(const KeyframeGraph& graph, int64_t id,
                                             const StereoCalib& calib,
                                             const NewPointOptions& options) {
  std::vector<NewPoint> out;
  const MapperKeyframe* kf = graph.keyframe(id);
  if (!kf || options.covisible_keyframes == 0) return out;
  const View a = view_of(*kf, calib.cam0);
  std::vector<bool> used_a(a.free.size(), false);
  for (int64_t other : graph.most_covisible(id, options.covisible_keyframes)) {
    const View b = view_of(*graph.keyframe(other), calib.cam0);
    const PairTriangulator pair(a, b, calib.cam0.intrinsics, options);
    std::vector<bool> used_b(b.free.size(), false);
    for (size_t i = 0; i < a.free.size(); ++i) {
      if (used_a[i]) continue;
      const int j = pair.match(a.free[i], used_b);
      NewPoint p;
      if (j < 0 || !pair.triangulate(a.free[i], b.free[static_cast<size_t>(j)], &p.p_w)) continue;
      p.a = {id, a.free[i].index};
      p.b = {other, b.free[static_cast<size_t>(j)].index};
      used_a[i] = true;
      used_b[static_cast<size_t>(j)] = true;
      out.push_back(p);
    }
  }
  return out;
}

}  // namespace hs
