#pragma once
// Synthetic scene for the direct-alignment tests and bench (header only, no disk): a closed box
// room with a free-standing panel, every face textured with multi-octave value noise, rendered
// by casting each pixel's ray through a PinholeRadtan camera (distortion included). The world
// frame is the reference camera frame: x right, y down, z forward.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

#include "common/calib/pinhole_radtan.h"

namespace hs::direct_test {

struct TexturedRect {
  Eigen::Vector3d normal;  // unit; the plane is normal . p = offset
  double offset = 0.0;
  Eigen::Vector3d axis_u, axis_v;  // texture axes in the plane (unit)
  uint64_t seed = 0;
  Eigen::Vector2d centre{0, 0};  // extent in (axis_u, axis_v) coordinates: unbounded by default
  Eigen::Vector2d half_size{std::numeric_limits<double>::infinity(),
                            std::numeric_limits<double>::infinity()};
};

// Smooth value noise in about [-1, 1]: random lattice values, quintic interpolation.
inline double value_noise(double x, double y, uint64_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto lattice = [seed](int64_t ix, int64_t iy) {
    uint64_t h = seed * 0x9E3779B97F4A7C15ull ^ static_cast<uint64_t>(ix) * 0xC2B2AE3D27D4EB4Full ^
                 static_cast<uint64_t>(iy) * 0x165667B19E3779F9ull;
    h ^= h >> 33;
    h *= 0xFF51AFD7ED558CCDull;
    h ^= h >> 33;
    return static_cast<double>(h >> 11) * (2.0 / 9007199254740992.0) - 1.0;
  };
  const auto fade = [](double t) { return t * t * t * (t * (6.0 * t - 15.0) + 10.0); };
  const int64_t ix = static_cast<int64_t>(fx), iy = static_cast<int64_t>(fy);
  const double u = fade(x - fx), v = fade(y - fy);
  const double a = lattice(ix, iy) + u * (lattice(ix + 1, iy) - lattice(ix, iy));
  const double b = lattice(ix, iy + 1) + u * (lattice(ix + 1, iy + 1) - lattice(ix, iy + 1));
  return a + v * (b - a);
}

// Grey level of a texture at plane coordinates (metres): octaves from 24 cm down to 3 cm.
inline double texture(const Eigen::Vector2d& st, uint64_t seed) {
  double sum = 0.0, amplitude = 1.0, spacing = 0.24;
  for (int octave = 0; octave < 4; ++octave, amplitude *= 0.7, spacing *= 0.5) {
    sum += amplitude * value_noise(st.x() / spacing, st.y() / spacing, seed * 16 + octave);
  }
  return 100.0 + 50.0 * std::clamp(sum, -1.6, 1.6);
}

class RoomScene {
 public:
  explicit RoomScene(const PinholeRadtan& cam) : cam_(cam) {
    const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(),
                          z = Eigen::Vector3d::UnitZ();
    rects_ = {{-z, -4.0, x, y, 1},                             // back wall z = 4
              {z, -3.0, x, y, 2},                              // wall behind, z = -3
              {-y, -1.3, x, z, 3},                             // floor y = 1.3
              {y, -1.6, x, z, 4},                              // ceiling y = -1.6
              {x, -2.2, z, y, 5},                              // left wall x = -2.2
              {-x, -2.5, z, y, 6},                             // right wall x = 2.5
              {-z, -2.3, x, y, 7, {0.9, 0.2}, {0.45, 0.35}}};  // panel at z = 2.3
    rays_.resize(static_cast<size_t>(cam.width) * cam.height);
    for (int v = 0; v < cam.height; ++v) {
      for (int u = 0; u < cam.width; ++u) {
        rays_[static_cast<size_t>(v) * cam.width + u] =
            cam.unproject_normalised(Eigen::Vector2d(u, v)).homogeneous();
      }
    }
  }

  const PinholeRadtan& camera() const { return cam_; }

  // Point (camera frame) seen along the ray (x, y, 1) from camera pose T_w_c, with the surface
  // it lies on; false when nothing is hit.
  bool cast(const Eigen::Isometry3d& T_w_c, const Eigen::Vector3d& ray, Eigen::Vector3d* p_c,
            const TexturedRect** hit = nullptr) const {
    const Eigen::Vector3d o = T_w_c.translation(), d = T_w_c.linear() * ray;
    double best = std::numeric_limits<double>::infinity();
    for (const TexturedRect& r : rects_) {
      const double den = r.normal.dot(d);
      if (std::abs(den) < 1e-12) continue;
      const double t = (r.offset - r.normal.dot(o)) / den;
      if (!(t > 0.0) || t >= best) continue;
      const Eigen::Vector3d p = o + t * d;
      const Eigen::Vector2d st(r.axis_u.dot(p), r.axis_v.dot(p));
      if (((st - r.centre).cwiseAbs() - r.half_size).maxCoeff() > 0.0) continue;
      best = t;
      if (hit) *hit = &r;
    }
    if (!std::isfinite(best)) return false;
    *p_c = best * ray;
    return true;
  }

  // The surface seen at pixel uv (nullptr: none).
  const TexturedRect* surface_at(const Eigen::Isometry3d& T_w_c, const Eigen::Vector2d& uv) const {
    const TexturedRect* hit = nullptr;
    Eigen::Vector3d p;
    return cast(T_w_c, cam_.unproject_normalised(uv).homogeneous(), &p, &hit) ? hit : nullptr;
  }

  // True when the pixels within `radius` of uv all see the same surface as uv (no occlusion
  // boundary or seam nearby).
  bool on_one_surface(const Eigen::Isometry3d& T_w_c, const Eigen::Vector2d& uv,
                      double radius) const {
    const TexturedRect* centre = surface_at(T_w_c, uv);
    for (int k = 0; k < 8 && centre; ++k) {
      const double angle = k * M_PI / 4.0;
      const Eigen::Vector2d q = uv + radius * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      if (surface_at(T_w_c, q) != centre) return false;
    }
    return centre != nullptr;
  }

  // The camera-frame point seen at pixel uv.
  bool point_at(const Eigen::Isometry3d& T_w_c, const Eigen::Vector2d& uv,
                Eigen::Vector3d* p_c) const {
    return cast(T_w_c, cam_.unproject_normalised(uv).homogeneous(), p_c);
  }

  // I = gain * texture + offset + N(0, noise_sigma), rounded and clamped to 8 bits. The texture
  // is blurred by a Gaussian of `blur_sigma` pixels first, as optics and pixel area do.
  cv::Mat render(const Eigen::Isometry3d& T_w_c, double gain = 1.0, double offset = 0.0,
                 double noise_sigma = 0.0, uint32_t noise_seed = 1, double blur_sigma = 0.7) const {
    cv::Mat radiance(cam_.height, cam_.width, CV_32FC1);
    for (int v = 0; v < cam_.height; ++v) {
      float* row = radiance.ptr<float>(v);
      for (int u = 0; u < cam_.width; ++u) {
        Eigen::Vector3d p_c;
        const TexturedRect* rect = nullptr;
        row[u] = 0.f;
        if (cast(T_w_c, rays_[static_cast<size_t>(v) * cam_.width + u], &p_c, &rect)) {
          const Eigen::Vector3d p_w = T_w_c * p_c;
          row[u] = static_cast<float>(
              texture({rect->axis_u.dot(p_w), rect->axis_v.dot(p_w)}, rect->seed));
        }
      }
    }
    if (blur_sigma > 0.0) cv::GaussianBlur(radiance, radiance, cv::Size(0, 0), blur_sigma);
    cv::Mat img(cam_.height, cam_.width, CV_8UC1);
    std::mt19937 rng(noise_seed);
    std::normal_distribution<double> noise(0.0, 1.0);
    for (int v = 0; v < cam_.height; ++v) {
      const float* in = radiance.ptr<float>(v);
      uint8_t* out = img.ptr<uint8_t>(v);
      for (int u = 0; u < cam_.width; ++u) {
        double value = gain * in[u] + offset;
        if (noise_sigma > 0.0) value += noise_sigma * noise(rng);
        out[u] = static_cast<uint8_t>(std::clamp(std::lround(value), 0L, 255L));
      }
    }
    return img;
  }

 private:
  PinholeRadtan cam_;
  std::vector<TexturedRect> rects_;
  std::vector<Eigen::Vector3d> rays_;  // (x, y, 1) undistorted, per pixel
};

// Pose from a translation and a rotation vector (radians).
inline Eigen::Isometry3d make_pose(const Eigen::Vector3d& t, const Eigen::Vector3d& rotvec) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (rotvec.norm() > 0.0)
    T.linear() = Eigen::AngleAxisd(rotvec.norm(), rotvec.normalized()).matrix();
  T.translation() = t;
  return T;
}

// T_cur_ref of the tests: 8.5 cm and 3 degrees, a fast inter-frame motion at 20 Hz.
inline Eigen::Isometry3d test_motion() {
  return make_pose({0.06, -0.03, 0.05},
                   Eigen::Vector3d(0.3, -1.0, 0.5).normalized() * 3.0 * M_PI / 180.0);
}

// Pixels with the strongest gradient, one per cell of a cols x rows grid (at least `margin`
// pixels from the border), as camera-frame points of `scene` seen from T_w_c.
inline std::vector<Eigen::Vector3d> select_points(const RoomScene& scene, const cv::Mat& img,
                                                  const Eigen::Isometry3d& T_w_c, int cols,
                                                  int rows, int margin = 12) {
  std::vector<Eigen::Vector3d> points;
  const int w = img.cols - 2 * margin, h = img.rows - 2 * margin;
  for (int cy = 0; cy < rows; ++cy) {
    for (int cx = 0; cx < cols; ++cx) {
      int best = -1, bu = 0, bv = 0;
      for (int v = margin + cy * h / rows; v < margin + (cy + 1) * h / rows; ++v) {
        for (int u = margin + cx * w / cols; u < margin + (cx + 1) * w / cols; ++u) {
          const int gx = img.at<uint8_t>(v, u + 1) - img.at<uint8_t>(v, u - 1);
          const int gy = img.at<uint8_t>(v + 1, u) - img.at<uint8_t>(v - 1, u);
          if (gx * gx + gy * gy > best) {
            best = gx * gx + gy * gy;
            bu = u;
            bv = v;
          }
        }
      }
      Eigen::Vector3d p;
      if (scene.point_at(T_w_c, Eigen::Vector2d(bu, bv), &p)) points.push_back(p);
    }
  }
  return points;
}

}  // namespace hs::direct_test
