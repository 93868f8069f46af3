#include "common/sim/render.h"
#include "common/core/monotonic_clock.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <ctime>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#include "common/sim/render_raster.h"
#include "common/sim/render_rays.h"
#include "common/sim/render_simd.h"
#include "common/sim/texture.h"

namespace hs::sim {
namespace {

using detail::CameraRays;
using detail::kGrid;
using detail::kGridPad;
using detail::kTile;
using detail::kTilePixels;
using detail::PoseSetup;
using detail::QuadCoeffs;
using simd::v4f;
using simd::v4i;

// Coverage samples of an edge pixel: a 16-rooks lattice (x = (i + 0.5) / 16,
// y = (5 i mod 16 + 0.5) / 16), so even axis-aligned edges get 1/16 coverage steps.
constexpr int kSub = 16;
constexpr double kBackgroundDepthM = 10.0;  // for motion estimates where nothing is seen

// log2 for mip selection: exponent + quadratic on the mantissa (error < 0.01).
inline float fast_log2(float x) {
  uint32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  const float e = static_cast<float>(static_cast<int>((bits >> 23) & 255) - 127);
  bits = (bits & 0x7FFFFFu) | 0x3F800000u;
  float m;
  std::memcpy(&m, &bits, sizeof m);
  return e + (-0.34484843f * m + 2.02466578f) * m - 1.67487759f;
}

}  // namespace

struct Renderer::Scene {
  World world;
  int texture_size = 0;
  std::vector<std::unique_ptr<Texture>> textures;
  std::vector<const Texture*> quad_texture;  // per quad
};

class Renderer::Impl {
 public:
  Impl(const Scene& scene, const PinholeRadtan& camera, const RenderOptions& options);
  void render_radiance(const Eigen::Isometry3d& T_w_c, const FrameParams& frame, float* out);

  PinholeRadtan camera;
  RenderOptions options;
  Photometric photometric;
  RenderStats stats;
  std::vector<float> radiance;  // render()'s buffer, reused between frames

 private:
  void setup_pose(const Eigen::Isometry3d& T_w_c, PoseSetup* setup) const;
  // Writes the tile's radiance (rows x cols pixels) to out with the given row stride; returns
  // the number of anti-aliased edge pixels.
  int shade_tile(const PoseSetup& setup, int tile, const int32_t* ids, float* out, int stride,
                 int rows, int cols);
  // Radiance of quad q along n (a multiple of 4, <= kTile) rays (x, y) with their pixel
  // footprint scales.
  void shade_run(const QuadCoeffs& q, const float* xs, const float* ys, const float* scales, int n,
                 float* out) const;
  // shade_run for n <= kTile consecutive pixels of a tile row from pixel-table index k.
  void shade_span(const QuadCoeffs& q, size_t k, int n, float* out) const;
  // Finds which quads cover how much of edge pixel (px, py) and queues their shading, to be
  // added to *pixel; returns the background's share.
  float cover_edge_pixel(const PoseSetup& setup, int tile, int px, int py, float* pixel);
  // Shades the queued edge samples, batched per quad, and adds them to their pixels.
  void shade_edge_samples(const PoseSetup& setup);
  // Image motion (pixels) of the tile between exposure start and end.
  double tile_motion(int tile, const Eigen::Isometry3d& T_s_c, const Eigen::Isometry3d& T_e_c,
                     const int32_t* ids, const float* best_w) const;
  void blur_tile(int tile, int samples, const FrameParams& frame, float* out);

  const Scene& scene_;
  const CameraRays rays_;
  // Bilinear weights of the coverage samples between a pixel's corner rays.
  float sub_w00_[kSub], sub_w01_[kSub], sub_w10_[kSub], sub_w11_[kSub];

  // A quad's share of an edge pixel, waiting to be shaded.
  struct EdgeSample {
    int32_t quad;
    float x, y, pixel_scale, weight;
    float* pixel;
  };
  std::vector<EdgeSample> edge_samples_;

  PoseSetup main_setup_;
  std::vector<PoseSetup> blur_setups_;  // (samples, index) -> n(n-1)/2 + index
  std::vector<bool> blur_ready_;
  // Nearest quad (-1: none) and its 1/z at every pixel corner, kGridPad per tile, frame pose.
  std::vector<int32_t> ids_;
  std::vector<float> best_w_;
};

Renderer::Impl::Impl(const Scene& scene, const PinholeRadtan& cam, const RenderOptions& opts)
    : camera(cam),
      options(opts),
      photometric(cam, opts.photometric),
      radiance(static_cast<size_t>(cam.width) * cam.height),
      scene_(scene),
      rays_(cam),
      ids_(rays_.corner_x.size()),
      best_w_(rays_.corner_x.size()) {
  for (int i = 0; i < kSub; ++i) {
    const float fu = (i + 0.5f) / kSub, fv = ((5 * i) % kSub + 0.5f) / kSub;
    sub_w00_[i] = (1 - fu) * (1 - fv);
    sub_w01_[i] = fu * (1 - fv);
    sub_w10_[i] = (1 - fu) * fv;
    sub_w11_[i] = fu * fv;
  }
  const int max_n = std::max(options.max_blur_samples, 1);
  blur_setups_.resize(static_cast<size_t>(max_n * (max_n + 1) / 2));
}

void Renderer::Impl::setup_pose(const Eigen::Isometry3d& T_w_c, PoseSetup* setup) const {
  detail::setup_pose(scene_.world, scene_.quad_texture, scene_.texture_size, rays_, options.near_m,
                     T_w_c, setup);
}

void Renderer::Impl::shade_run(const QuadCoeffs& q, const float* xs, const float* ys,
                               const float* scales, int n, float* out) const {
  alignas(16) float us[kTile], vs[kTile];
  v4f rho2 = v4f{};
  for (int i = 0; i < n; i += 4) {
    const v4f x = simd::load(xs + i), y = simd::load(ys + i);
    const v4f inv_w = 1.0f / (q.wa * x + q.wb * y + q.wc);
    const v4f u = (q.ua * x + q.ub * y + q.uc) * inv_w;
    const v4f v = (q.va * x + q.vb * y + q.vc) * inv_w;
    if (i == 0 || i == n - 4) {
      // Texel footprint of a pixel: derivatives of (u, v) along x and y, scaled to pixels.
      // It varies slowly, so the run's two ends bound it.
      const v4f k = simd::load(scales + i);
      const v4f du_dx = (q.ua - u * q.wa) * inv_w, du_dy = (q.ub - u * q.wb) * inv_w;
      const v4f dv_dx = (q.va - v * q.wa) * inv_w, dv_dy = (q.vb - v * q.wb) * inv_w;
      rho2 = simd::max(
          rho2, simd::max(du_dx * du_dx + dv_dx * dv_dx, du_dy * du_dy + dv_dy * dv_dy) * (k * k));
    }
    simd::store(us + i, u + q.u_offset);
    simd::store(vs + i, v + q.v_offset);
  }
  // The run shares the largest footprint's lod, so no pixel aliases.
  const float lod = 0.5f * fast_log2(std::max(simd::horizontal_max(rho2), 1e-12f));
  q.texture->sample(us, vs, n, lod, q.brightness, out);
}

float Renderer::Impl::cover_edge_pixel(const PoseSetup& setup, int tile, int px, int py,
                                       float* pixel) {
  // 16 coverage samples with rays interpolated between the pixel's corner rays. Each quad seen
  // is shaded later (batched per quad) at the mean ray of its samples, weighted by coverage.
  const size_t g = static_cast<size_t>(tile) * kGridPad + static_cast<size_t>(py * kGrid + px);
  const std::vector<float>& cx = rays_.corner_x;
  const std::vector<float>& cy = rays_.corner_y;
  alignas(16) float sx[kSub], sy[kSub], bw[kSub];
  alignas(16) int32_t sid[kSub];
  for (int i = 0; i < kSub; ++i) {
    sx[i] = sub_w00_[i] * cx[g] + sub_w01_[i] * cx[g + 1] + sub_w10_[i] * cx[g + kGrid] +
            sub_w11_[i] * cx[g + kGrid + 1];
    sy[i] = sub_w00_[i] * cy[g] + sub_w01_[i] * cy[g + 1] + sub_w10_[i] * cy[g + kGrid] +
            sub_w11_[i] * cy[g + kGrid + 1];
  }
  detail::nearest_quads(setup, tile, sx, sy, kSub, sid, bw);
  const float scale = rays_.pixel_scale[static_cast<size_t>(tile) * kTilePixels +
                                        static_cast<size_t>(py * kTile + px)];
  bool done[kSub] = {};
  float background = 0.0f;
  for (int i = 0; i < kSub; ++i) {
    if (done[i]) continue;
    int count = 0;
    float mx = 0.0f, my = 0.0f;
    for (int j = i; j < kSub; ++j) {
      if (sid[j] != sid[i]) continue;
      done[j] = true;
      ++count;
      mx += sx[j];
      my += sy[j];
    }
    const float weight = static_cast<float>(count) / kSub;
    if (sid[i] < 0) {
      background += weight * options.background;
    } else {
      edge_samples_.push_back({sid[i], mx / count, my / count, scale, weight, pixel});
    }
  }
  return background;
}

void Renderer::Impl::shade_edge_samples(const PoseSetup& setup) {
  std::sort(edge_samples_.begin(), edge_samples_.end(),
            [](const EdgeSample& a, const EdgeSample& b) { return a.quad < b.quad; });
  alignas(16) float xs[kTile], ys[kTile], ks[kTile], values[kTile];
  for (size_t i = 0; i < edge_samples_.size();) {
    // Up to kTile samples of one quad, padded to whole vectors by repeating the last one.
    size_t end = i + 1;
    while (end < edge_samples_.size() && end - i < kTile &&
           edge_samples_[end].quad == edge_samples_[i].quad) {
      ++end;
    }
    const int n = static_cast<int>(end - i), padded = (n + 3) / 4 * 4;
    for (int j = 0; j < padded; ++j) {
      const EdgeSample& e = edge_samples_[i + static_cast<size_t>(std::min(j, n - 1))];
      xs[j] = e.x;
      ys[j] = e.y;
      ks[j] = e.pixel_scale;
    }
    shade_run(setup.quads[static_cast<size_t>(edge_samples_[i].quad)], xs, ys, ks, padded, values);
    for (int j = 0; j < n; ++j) {
      const EdgeSample& e = edge_samples_[i + static_cast<size_t>(j)];
      *e.pixel += e.weight * values[j];
    }
    i = end;
  }
  edge_samples_.clear();
}

int Renderer::Impl::shade_tile(const PoseSetup& setup, int tile, const int32_t* ids, float* out,
                               int stride, int rows, int cols) {
  int edge_pixels = 0;
  constexpr int32_t kEdge = -2;
  const size_t base = static_cast<size_t>(tile) * kTilePixels;
  for (int py = 0; py < rows; ++py) {
    const int32_t* top = ids + py * kGrid;
    const int32_t* bottom = top + kGrid;
    float* row = out + static_cast<size_t>(py) * stride;
    const size_t k0 = base + static_cast<size_t>(py * kTile);
    // Per pixel: the quad all four corners see (-1: none), or kEdge.
    alignas(16) int32_t seen[kTile];
    for (int px = 0; px < kTile; px += 4) {
      const v4i id = simd::load(top + px);
      const v4i same = (id == simd::load(top + px + 1)) & (id == simd::load(bottom + px)) &
                       (id == simd::load(bottom + px + 1));
      simd::store(seen + px, same ? id : v4i{} + kEdge);
    }
    // Runs of pixels seeing the same quad are shaded together (vectorised).
    for (int px = 0; px < cols;) {
      const int32_t id = seen[px];
      int end = px + 1;
      while (end < cols && seen[end] == id) ++end;
      if (id == kEdge) {
        for (int p = px; p < end; ++p) row[p] = cover_edge_pixel(setup, tile, p, py, row + p);
        edge_pixels += end - px;
      } else if (id < 0) {
        std::fill(row + px, row + end, options.background);
      } else {
        shade_span(setup.quads[static_cast<size_t>(id)], k0 + static_cast<size_t>(px), end - px,
                   row + px);
      }
      px = end;
    }
  }
  shade_edge_samples(setup);
  return edge_pixels;
}

void Renderer::Impl::shade_span(const QuadCoeffs& q, size_t k, int n, float* out) const {
  if (n % 4 == 0) {
    shade_run(q, &rays_.centre_x[k], &rays_.centre_y[k], &rays_.pixel_scale[k], n, out);
    return;
  }
  // Pad to whole vectors by repeating the last pixel.
  alignas(16) float xs[kTile], ys[kTile], ks[kTile], values[kTile];
  const int padded = (n + 3) / 4 * 4;
  for (int i = 0; i < padded; ++i) {
    const size_t j = k + static_cast<size_t>(std::min(i, n - 1));
    xs[i] = rays_.centre_x[j];
    ys[i] = rays_.centre_y[j];
    ks[i] = rays_.pixel_scale[j];
  }
  shade_run(q, xs, ys, ks, padded, values);
  std::copy(values, values + n, out);
}

double Renderer::Impl::tile_motion(int tile, const Eigen::Isometry3d& T_s_c,
                                   const Eigen::Isometry3d& T_e_c, const int32_t* ids,
                                   const float* best_w) const {
  const size_t g0 = static_cast<size_t>(tile) * kGridPad;
  double motion = 0.0;
  for (const int g : {0, kTile, kTile * kGrid, kTile * kGrid + kTile, kTile / 2 * (kGrid + 1)}) {
    const double z = ids[g] >= 0 ? 1.0 / best_w[g] : kBackgroundDepthM;
    const Eigen::Vector3d p_c(rays_.corner_x[g0 + g] * z, rays_.corner_y[g0 + g] * z, z);
    const Eigen::Vector3d p_s = T_s_c * p_c, p_e = T_e_c * p_c;
    if (p_s.z() < options.near_m || p_e.z() < options.near_m) {
      return std::numeric_limits<double>::infinity();
    }
    const Eigen::Vector2d d = p_s.head<2>() / p_s.z() - p_e.head<2>() / p_e.z();
    motion = std::max(motion, std::hypot(camera.fx * d.x(), camera.fy * d.y()));
  }
  return motion;
}

void Renderer::Impl::blur_tile(int tile, int samples, const FrameParams& frame, float* out) {
  // `samples` is odd: the middle sub-exposure pose is the frame pose, already rendered in out.
  const int width = rays_.width, u0 = rays_.tile_u0(tile), v0 = rays_.tile_v0(tile);
  const int rows = std::min(kTile, rays_.height - v0), cols = std::min(kTile, width - u0);
  float* tile_out = out + static_cast<size_t>(v0) * width + u0;
  float sum[kTilePixels] = {};
  for (int py = 0; py < rows; ++py) {
    std::copy(tile_out + static_cast<size_t>(py) * width,
              tile_out + static_cast<size_t>(py) * width + cols, sum + py * kTile);
  }
  alignas(16) int32_t ids[kGridPad];
  alignas(16) float best_w[kGridPad];
  float sub[kTilePixels];
  for (int k = 0; k < samples; ++k) {
    if (2 * k + 1 == samples) continue;
    const size_t slot = static_cast<size_t>(samples * (samples - 1) / 2 + k);
    if (!blur_ready_[slot]) {
      setup_pose(frame.T_w_c_at((k + 0.5) / samples), &blur_setups_[slot]);
      blur_ready_[slot] = true;
    }
    detail::nearest_quads(blur_setups_[slot], tile, rays_.corner_xs(tile), rays_.corner_ys(tile),
                          kGridPad, ids, best_w);
    shade_tile(blur_setups_[slot], tile, ids, sub, kTile, kTile, kTile);
    for (int i = 0; i < kTilePixels; ++i) sum[i] += sub[i];
  }
  for (int py = 0; py < rows; ++py) {
    for (int px = 0; px < cols; ++px) {
      tile_out[static_cast<size_t>(py) * width + px] = sum[py * kTile + px] / samples;
    }
  }
}

void Renderer::Impl::render_radiance(const Eigen::Isometry3d& T_w_c, const FrameParams& frame,
                                     float* out) {
  const int tiles = rays_.tiles(), width = rays_.width;
  int64_t t0 = thread_cpu_ns();
  setup_pose(T_w_c, &main_setup_);
  stats.setup_ns += thread_cpu_ns() - t0;

  t0 = thread_cpu_ns();
  for (int t = 0; t < tiles; ++t) {
    const size_t g = static_cast<size_t>(t) * kGridPad;
    detail::nearest_quads(main_setup_, t, rays_.corner_xs(t), rays_.corner_ys(t), kGridPad,
                          &ids_[g], &best_w_[g]);
  }
  stats.visibility_ns += thread_cpu_ns() - t0;

  t0 = thread_cpu_ns();
  for (int t = 0; t < tiles; ++t) {
    const int u0 = rays_.tile_u0(t), v0 = rays_.tile_v0(t);
    stats.edge_pixels +=
        shade_tile(main_setup_, t, &ids_[static_cast<size_t>(t) * kGridPad],
                   out + static_cast<size_t>(v0) * width + u0, width,
                   std::min(kTile, rays_.height - v0), std::min(kTile, width - u0));
  }
  stats.shading_ns += thread_cpu_ns() - t0;

  if (!options.motion_blur || !frame.T_w_c_at) return;
  t0 = thread_cpu_ns();
  const Eigen::Isometry3d T_s_c = frame.T_w_c_at(0.0).inverse() * T_w_c;
  const Eigen::Isometry3d T_e_c = frame.T_w_c_at(1.0).inverse() * T_w_c;
  blur_ready_.assign(blur_setups_.size(), false);
  // Odd sample counts, so the frame's own render is the middle sample.
  const int max_n = std::max(1, options.max_blur_samples - 1 + options.max_blur_samples % 2);
  for (int t = 0; t < tiles; ++t) {
    const size_t g = static_cast<size_t>(t) * kGridPad;
    const double motion = tile_motion(t, T_s_c, T_e_c, &ids_[g], &best_w_[g]);
    if (!(motion > options.blur_step_px)) continue;  // NaN-safe
    const int n =
        std::min<int>(max_n, static_cast<int>(std::ceil(motion / options.blur_step_px)) | 1);
    if (n < 3) continue;
    blur_tile(t, n, frame, out);
    ++stats.blurred_tiles;
  }
  stats.blur_ns += thread_cpu_ns() - t0;
}

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("Renderer: " + what);
}

void validate(const PinholeRadtan& c, const RenderOptions& o) {
  require(c.width > 0 && c.height > 0 && c.fx > 0 && c.fy > 0,
          "camera needs a size and fx, fy > 0");
  require(o.near_m > 0, "near_m must be > 0");
  require(o.blur_step_px > 0 && o.max_blur_samples >= 1, "bad motion blur options");
  require(o.texture_size >= 16 && (o.texture_size & (o.texture_size - 1)) == 0,
          "texture_size must be a power of two >= 16");
}

}  // namespace

Renderer::Renderer(const World& world, const PinholeRadtan& camera, const RenderOptions& options) {
  validate(camera, options);
  for (size_t i = 0; i < world.quads.size(); ++i) {
    const TexturedQuad& q = world.quads[i];
    require(std::isfinite(q.metres_per_tile) && q.metres_per_tile > 0 && q.brightness >= 0 &&
                q.p0_w.allFinite() && q.edge_u_w.allFinite() && q.edge_v_w.allFinite(),
            "world quad " + std::to_string(i) + " has a bad geometry, tile size or brightness");
  }
  const int size = options.texture_size;
  auto scene = std::make_shared<Scene>();
  scene->world = world;
  scene->texture_size = size;
  std::map<std::pair<int, uint32_t>, const Texture*> made;
  for (const TexturedQuad& q : world.quads) {
    const auto key = std::make_pair(static_cast<int>(q.texture), q.texture_seed);
    auto it = made.find(key);
    if (it == made.end()) {
      scene->textures.push_back(std::make_unique<Texture>(q.texture, q.texture_seed, size));
      it = made.emplace(key, scene->textures.back().get()).first;
    }
    scene->quad_texture.push_back(it->second);
  }
  scene_ = std::move(scene);
  impl_ = std::make_unique<Impl>(*scene_, camera, options);
}

Renderer::Renderer(const Renderer& shares_scene_with, const PinholeRadtan& camera,
                   const RenderOptions& options)
    : scene_(shares_scene_with.scene_) {
  validate(camera, options);
  impl_ = std::make_unique<Impl>(*scene_, camera, options);
}

Renderer::~Renderer() = default;

cv::Mat Renderer::render_radiance(const Eigen::Isometry3d& T_w_c, const FrameParams& frame) {
  cv::Mat radiance = cv::Mat::zeros(impl_->camera.height, impl_->camera.width, CV_32FC1);
  if (!frame.blackout) impl_->render_radiance(T_w_c, frame, radiance.ptr<float>());
  return radiance;
}

cv::Mat Renderer::render(const Eigen::Isometry3d& T_w_c, const FrameParams& frame) {
  cv::Mat image;
  if (frame.blackout) {
    image = cv::Mat::zeros(impl_->camera.height, impl_->camera.width, CV_8UC1);
  } else {
    impl_->render_radiance(T_w_c, frame, impl_->radiance.data());
    const int64_t t0 = thread_cpu_ns();
    impl_->photometric.apply(impl_->radiance.data(), frame.gain, frame.noise_seed, &image);
    impl_->stats.photometric_ns += thread_cpu_ns() - t0;
  }
  ++impl_->stats.images;
  return image;
}

const PinholeRadtan& Renderer::camera() const {
  return impl_->camera;
}
const RenderOptions& Renderer::options() const {
  return impl_->options;
}
const RenderStats& Renderer::stats() const {
  return impl_->stats;
}
void Renderer::reset_stats() {
  impl_->stats = {};
}

}  // namespace hs::sim
