#include "common/features/epipolar_points.h"

#include <cmath>
#include <limits>
#include <optional>

#include "common/features/descriptor_match.h"
#include "common/geometry/triangulation.h"

namespace hs {
namespace {

class PairTriangulator {
 public:
  PairTriangulator(const FreeKeypoints& a, const FreeKeypoints& b, const PinholeRadtan& cam,
                   const EpipolarPointOptions& o)
      : a_(a), b_(b), cam_(cam), o_(o), T_a_b_(a.T_w_c().inverse() * b.T_w_c()) {
    T_b_a_ = T_a_b_.inverse();
    min_cos_ = std::cos(o.min_parallax_deg * M_PI / 180.0);
  }

  // The best match of a's keypoint k among b's unused keypoints (-1: none).
  int match(const FreeKeypoints::Keypoint& k, const std::vector<bool>& used_b) const {
    // The epipolar plane's normal in b (E f_a, E = [t_b_a]x R_b_a).
    Eigen::Vector3d n = T_b_a_.translation().cross(T_b_a_.linear() * k.f_c);
    if (n.norm() < 1e-12) return -1;
    n.normalize();
    int best = -1, best_d = std::numeric_limits<int>::max(), second_d = best_d;
    const std::vector<FreeKeypoints::Keypoint>& kb = b_.keypoints();
    for (size_t j = 0; j < kb.size(); ++j) {
      if (used_b[j]) continue;
      const FreeKeypoints::Keypoint& c = kb[j];
      // Distance from the epipolar plane as an angle, against the pixel tolerance as one.
      if (std::abs(c.f_c.dot(n)) > o_.epipolar_px * std::pow(o_.octave_scale, c.octave) / cam_.fx)
        continue;
      if (c.f_w.dot(k.f_w) > min_cos_) continue;  // too little parallax to place it
      const int d = hamming256(k.descriptor, c.descriptor);
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

  bool triangulate(const FreeKeypoints::Keypoint& ka, const FreeKeypoints::Keypoint& kb,
                   Eigen::Vector3d* p_w) const {
    const std::optional<Eigen::Vector3d> p_a =
        triangulate_two_view(ka.f_c.head<2>() / ka.f_c.z(), kb.f_c.head<2>() / kb.f_c.z(), T_a_b_);
    if (!p_a) return false;
    *p_w = a_.T_w_c() * *p_a;
    if (!reprojects(a_, ka, *p_w) || !reprojects(b_, kb, *p_w)) return false;
    // The keypoints' pyramid levels say how far the point is from each camera relative to the
    // other; a point at odds with them is a wrong match.
    const double dist_a = (*p_w - a_.T_w_c().translation()).norm();
    const double dist_b = (*p_w - b_.T_w_c().translation()).norm();
    const double ratio_dist = dist_a / dist_b;
    const double ratio_octave = std::pow(o_.octave_scale, ka.octave - kb.octave);
    return ratio_dist * o_.scale_ratio_factor >= ratio_octave &&
           ratio_dist <= ratio_octave * o_.scale_ratio_factor;
  }

 private:
  bool reprojects(const FreeKeypoints& v, const FreeKeypoints::Keypoint& kp,
                  const Eigen::Vector3d& p_w) const {
    Eigen::Vector2d uv;
    if (!cam_.project(v.T_w_c().inverse() * p_w, &uv)) return false;
    const double tolerance = o_.max_reprojection_px * std::pow(o_.octave_scale, kp.octave);
    return (uv - kp.uv).squaredNorm() <= tolerance * tolerance;
  }

  const FreeKeypoints& a_;
  const FreeKeypoints& b_;
  const PinholeRadtan& cam_;
  const EpipolarPointOptions& o_;
  Eigen::Isometry3d T_a_b_, T_b_a_;
  double min_cos_ = 1.0;
};

}  // namespace

void FreeKeypoints::add(int index, const Eigen::Vector2d& uv, int octave,
                        const uint8_t* descriptor) {
  const Eigen::Vector3d f_c = camera_->unproject(uv);
  keypoints_.push_back({index, uv, octave, descriptor, f_c, T_w_c_.linear() * f_c});
}

std::vector<EpipolarPoint> triangulate_epipolar(const FreeKeypoints& a, const FreeKeypoints& b,
                                                const PinholeRadtan& camera,
                                                const EpipolarPointOptions& options,
                                                std::vector<bool>& used_a) {
  std::vector<EpipolarPoint> out;
  const PairTriangulator pair(a, b, camera, options);
  std::vector<bool> used_b(b.keypoints().size(), false);
  for (size_t i = 0; i < a.keypoints().size(); ++i) {
    if (used_a[i]) continue;
    const int j = pair.match(a.keypoints()[i], used_b);
    EpipolarPoint p;
    if (j < 0 || !pair.triangulate(a.keypoints()[i], b.keypoints()[static_cast<size_t>(j)], &p.p_w))
      continue;
    p.a = i;
    p.b = static_cast<size_t>(j);
    used_a[i] = true;
    used_b[p.b] = true;
    out.push_back(p);
  }
  return out;
}

}  // namespace hs
