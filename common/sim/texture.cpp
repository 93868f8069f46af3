#include "common/sim/texture.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/sim/render_rng.h"

namespace hs::sim {
namespace {

constexpr float kPi = 3.14159265358979f;

// std::hypot guards against overflow, which these small distances cannot reach; this is faster.
float length(float x, float y) {
  return std::sqrt(x * x + y * y);
}

// A periodic float image being painted, values nominally 0..1.
class Canvas {
 public:
  explicit Canvas(int n) : n_(n), px_(static_cast<size_t>(n) * n, 0.0f) {}
  int n() const { return n_; }
  float& at(int x, int y) { return px_[static_cast<size_t>(wrap(y)) * n_ + wrap(x)]; }
  std::vector<float>& pixels() { return px_; }

  void fill(float v) { std::fill(px_.begin(), px_.end(), v); }

  // Adds periodic value noise with `cells` lattice cells per side, quintic interpolation.
  void add_value_noise(Rng& rng, int cells, float amplitude) {
    cells = std::min(cells, n_);
    std::vector<float> lattice(static_cast<size_t>(cells) * cells);
    for (float& v : lattice) v = rng.uniform(-1.0f, 1.0f);
    const float cell = static_cast<float>(n_) / cells;
    for (int y = 0; y < n_; ++y) {
      const float fy = (y + 0.5f) / cell;
      const int y0 = static_cast<int>(fy);
      const float ty = smooth(fy - y0);
      const float* r0 = &lattice[static_cast<size_t>(y0 % cells) * cells];
      const float* r1 = &lattice[static_cast<size_t>((y0 + 1) % cells) * cells];
      for (int x = 0; x < n_; ++x) {
        const float fx = (x + 0.5f) / cell;
        const int x0 = static_cast<int>(fx), x1 = (x0 + 1) % cells;
        const float tx = smooth(fx - x0);
        const float a = r0[x0 % cells] + tx * (r0[x1] - r0[x0 % cells]);
        const float b = r1[x0 % cells] + tx * (r1[x1] - r1[x0 % cells]);
        px_[static_cast<size_t>(y) * n_ + x] += amplitude * (a + ty * (b - a));
      }
    }
  }

  // Fractal noise: octaves from `cells` doubling, amplitude halving.
  void add_fractal_noise(Rng& rng, int cells, int octaves, float amplitude) {
    for (int o = 0; o < octaves; ++o, cells *= 2, amplitude *= 0.5f) {
      add_value_noise(rng, cells, amplitude);
    }
  }

  // Paints a convex polygon (counter-clockwise in texel coordinates) with anti-aliased edges,
  // blending towards `value` with opacity `alpha`. Wraps around the tile.
  void fill_convex(const std::vector<float>& xs, const std::vector<float>& ys, float value,
                   float alpha) {
    const size_t m = xs.size();
    std::vector<float> nx(m), ny(m), off(m);
    for (size_t i = 0; i < m; ++i) {
      const size_t j = (i + 1) % m;
      const float ex = xs[j] - xs[i], ey = ys[j] - ys[i];
      const float len = std::max(length(ex, ey), 1e-6f);
      nx[i] = ey / len;  // outward normal of a counter-clockwise polygon
      ny[i] = -ex / len;
      off[i] = nx[i] * xs[i] + ny[i] * ys[i];
    }
    paint_bbox(xs, ys, value, alpha, [&](float px, float py) {
      float d = -1e9f;
      for (size_t i = 0; i < m; ++i) d = std::max(d, nx[i] * px + ny[i] * py - off[i]);
      return d;
    });
  }

  void fill_disc(float cx, float cy, float r, float value, float alpha) {
    paint_bbox({cx - r, cx + r}, {cy - r, cy + r}, value, alpha,
               [&](float px, float py) { return length(px - cx, py - cy) - r; });
  }

 private:
  static float smooth(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
  int wrap(int i) const { return i & (n_ - 1); }

  // Blends every texel of the shape's bounding box by its coverage, from the signed distance
  // (texels, negative inside) at the texel centre.
  template <typename SignedDistance>
  void paint_bbox(const std::vector<float>& xs, const std::vector<float>& ys, float value,
                  float alpha, SignedDistance sd) {
    const auto [xmin, xmax] = std::minmax_element(xs.begin(), xs.end());
    const auto [ymin, ymax] = std::minmax_element(ys.begin(), ys.end());
    for (int y = static_cast<int>(std::floor(*ymin)) - 1; y <= static_cast<int>(*ymax) + 1; ++y) {
      for (int x = static_cast<int>(std::floor(*xmin)) - 1; x <= static_cast<int>(*xmax) + 1; ++x) {
        const float cover = std::clamp(0.5f - sd(x + 0.5f, y + 0.5f), 0.0f, 1.0f) * alpha;
        if (cover > 0.0f) {
          float& p = at(x, y);
          p += cover * (value - p);
        }
      }
    }
  }

  int n_;
  std::vector<float> px_;
};

// Random shapes (rectangles, triangles, discs, bars) of `count` at about `size` texels.
void add_shapes(Canvas& c, Rng& rng, int count, float size) {
  for (int i = 0; i < count; ++i) {
    const float cx = rng.uniform(0.0f, static_cast<float>(c.n()));
    const float cy = rng.uniform(0.0f, static_cast<float>(c.n()));
    const float s = size * rng.uniform(0.5f, 1.5f);
    const float value =
        rng.uniform() < 0.5f ? rng.uniform(0.02f, 0.35f) : rng.uniform(0.65f, 0.98f);
    const float angle = rng.uniform(0.0f, 2.0f * kPi);
    const float ca = std::cos(angle), sa = std::sin(angle);
    const int type = static_cast<int>(rng.next() % 4);
    if (type == 2) {
      c.fill_disc(cx, cy, 0.5f * s, value, 1.0f);
      continue;
    }
    std::vector<float> lx, ly;  // local corners, counter-clockwise
    if (type == 0) {
      const float a = 0.5f * s, b = 0.5f * s * rng.uniform(0.4f, 1.0f);
      lx = {-a, a, a, -a};
      ly = {-b, -b, b, b};
    } else if (type == 1) {
      for (int k = 0; k < 3; ++k) {
        const float t = 2.0f * kPi * k / 3.0f + rng.uniform(-0.4f, 0.4f);
        lx.push_back(0.6f * s * std::cos(t));
        ly.push_back(0.6f * s * std::sin(t));
      }
    } else {
      const float a = 0.7f * s, b = 0.08f * s + 1.0f;
      lx = {-a, a, a, -a};
      ly = {-b, -b, b, b};
    }
    std::vector<float> xs, ys;
    for (size_t k = 0; k < lx.size(); ++k) {
      xs.push_back(cx + ca * lx[k] - sa * ly[k]);
      ys.push_back(cy + sa * lx[k] + ca * ly[k]);
    }
    // Rotation keeps the winding, so the shape stays counter-clockwise.
    c.fill_convex(xs, ys, value, 1.0f);
  }
}

void paint_mixed(Canvas& c, Rng& rng) {
  const float n = static_cast<float>(c.n());
  c.fill(0.5f);
  c.add_fractal_noise(rng, 4, 3, 0.25f);
  add_shapes(c, rng, 6, n / 5.0f);
  add_shapes(c, rng, 24, n / 12.0f);
  add_shapes(c, rng, 90, n / 30.0f);
  add_shapes(c, rng, 300, n / 80.0f);
  c.add_value_noise(rng, c.n() / 4, 0.04f);
}

void paint_brick(Canvas& c, Rng& rng) {
  const int n = c.n();
  const int rows = 16, bricks = 8;
  const float h = static_cast<float>(n) / rows, w = static_cast<float>(n) / bricks;
  const float mortar = std::max(1.5f, h * 0.12f);
  c.fill(0.82f);  // mortar
  for (int r = 0; r < rows; ++r) {
    const float shift = (r % 2) * 0.5f * w;
    for (int b = 0; b < bricks; ++b) {
      const float x0 = b * w + shift + 0.5f * mortar, x1 = (b + 1) * w + shift - 0.5f * mortar;
      const float y0 = r * h + 0.5f * mortar, y1 = (r + 1) * h - 0.5f * mortar;
      c.fill_convex({x0, x1, x1, x0}, {y0, y0, y1, y1}, rng.uniform(0.15f, 0.6f), 1.0f);
      // Chips and stains: small corners inside the bricks.
      for (int k = 0; k < 2; ++k) {
        const float cx = rng.uniform(x0, x1), cy = rng.uniform(y0, y1),
                    s = rng.uniform(2.f, h * 0.3f);
        c.fill_convex({cx, cx + s, cx + s, cx}, {cy, cy, cy + 0.6f * s, cy + 0.6f * s},
                      rng.uniform(0.05f, 0.9f), 0.7f);
      }
    }
  }
  c.add_fractal_noise(rng, 4, 2, 0.1f);
  c.add_value_noise(rng, n / 4, 0.06f);
}

void paint_blobs(Canvas& c, Rng& rng) {
  const float n = static_cast<float>(c.n());
  c.fill(0.0f);
  c.add_fractal_noise(rng, 6, 3, 1.0f);
  // A soft contrast curve turns the noise into blobs with steep but smooth borders.
  for (float& p : c.pixels()) p = 0.5f + 0.35f * std::tanh(2.5f * p);
  for (int i = 0; i < 60; ++i) {
    c.fill_disc(rng.uniform(0, n), rng.uniform(0, n), n * rng.uniform(0.01f, 0.05f),
                rng.uniform(0.05f, 0.95f), 0.8f);
  }
  // A sprinkle of hard-edged shapes gives corners among the smooth blobs.
  add_shapes(c, rng, 30, n / 25.0f);
  add_shapes(c, rng, 120, n / 70.0f);
  c.add_fractal_noise(rng, c.n() / 32, 2, 0.08f);
}

// Periodic jittered-grid Voronoi stones: value per stone, dark gaps where the two nearest
// sites are equidistant.
void add_stones(Canvas& c, Rng& rng, int cells, float weight) {
  const int n = c.n();
  const float cell = static_cast<float>(n) / cells;
  std::vector<float> sx(static_cast<size_t>(cells) * cells), sy(sx.size()), sv(sx.size());
  for (size_t i = 0; i < sx.size(); ++i) {
    sx[i] = rng.uniform(0.1f, 0.9f);
    sy[i] = rng.uniform(0.1f, 0.9f);
    sv[i] = rng.uniform(0.15f, 0.9f);
  }
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const float fx = (x + 0.5f) / cell, fy = (y + 0.5f) / cell;
      const int gx = static_cast<int>(fx), gy = static_cast<int>(fy);
      float d1 = 1e9f, d2 = 1e9f, v = 0.0f;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int cx = gx + dx, cy = gy + dy;
          const size_t i = static_cast<size_t>(((cy % cells + cells) % cells) * cells +
                                               ((cx % cells + cells) % cells));
          const float d = length(cx + sx[i] - fx, cy + sy[i] - fy);
          if (d < d1) {
            d2 = d1;
            d1 = d;
            v = sv[i];
          } else if (d < d2) {
            d2 = d;
          }
        }
      }
      const float gap = std::clamp((d2 - d1) * cell * 0.5f - 0.5f, 0.0f, 1.0f);  // ~1 texel AA
      float& p = c.at(x, y);
      p += weight * (0.08f + gap * (v - 0.08f) - p);
    }
  }
}

void paint_gravel(Canvas& c, Rng& rng) {
  c.fill(0.5f);
  add_stones(c, rng, 12, 1.0f);
  add_stones(c, rng, 48, 0.5f);
  c.add_fractal_noise(rng, c.n() / 16, 2, 0.08f);
}

void paint_plain(Canvas& c, Rng& rng) {
  c.fill(0.6f);
  c.add_value_noise(rng, 2, 0.02f);
}

}  // namespace

std::vector<uint8_t> generate_texture(TextureKind kind, uint32_t seed, int size) {
  if (size < 16 || (size & (size - 1)) != 0) {
    throw std::invalid_argument("texture size must be a power of two >= 16");
  }
  Rng rng(0x5EEDull * (static_cast<uint64_t>(kind) + 1) ^ (static_cast<uint64_t>(seed) << 20));
  Canvas c(size);
  switch (kind) {
    case TextureKind::kMixed:
      paint_mixed(c, rng);
      break;
    case TextureKind::kBrick:
      paint_brick(c, rng);
      break;
    case TextureKind::kBlobs:
      paint_blobs(c, rng);
      break;
    case TextureKind::kGravel:
      paint_gravel(c, rng);
      break;
    case TextureKind::kPlain:
      paint_plain(c, rng);
      break;
  }
  std::vector<uint8_t> out(c.pixels().size());
  for (size_t i = 0; i < out.size(); ++i) {
    out[i] = static_cast<uint8_t>(std::clamp(c.pixels()[i] * 255.0f + 0.5f, 0.0f, 255.0f));
  }
  return out;
}

Texture::Texture(TextureKind kind, uint32_t seed, int size) : size_(size), log2_size_(0) {
  while ((1 << log2_size_) < size) ++log2_size_;
  std::vector<uint8_t> level = generate_texture(kind, seed, size);
  for (int n = size; n >= 1; n /= 2) {
    offsets_.push_back(data_.size());
    for (int y = 0; y <= n; ++y) {
      const uint8_t* row = &level[static_cast<size_t>(y % n) * n];
      data_.insert(data_.end(), row, row + n);
      data_.push_back(row[0]);
    }
    if (n == 1) break;
    // Next level: 2x2 box filter.
    std::vector<uint8_t> next(static_cast<size_t>(n / 2) * (n / 2));
    for (int y = 0; y < n / 2; ++y) {
      for (int x = 0; x < n / 2; ++x) {
        const uint8_t* p = &level[static_cast<size_t>(2 * y) * n + 2 * x];
        next[static_cast<size_t>(y) * (n / 2) + x] =
            static_cast<uint8_t>((p[0] + p[1] + p[n] + p[n + 1] + 2) / 4);
      }
    }
    level = std::move(next);
  }
}

}  // namespace hs::sim
