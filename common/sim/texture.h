#pragma once
// Procedural, tileable grey textures with corners and edges at several scales, deterministic
// from (kind, seed), stored with a full mip pyramid and sampled with trilinear filtering.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "common/sim/render_simd.h"
#include "common/sim/world.h"

namespace hs::sim {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "Texture reads texel pairs as uint16");

class Texture {
 public:
  // size: texels per side, a power of two >= 16. Values are albedo 0..255.
  Texture(TextureKind kind, uint32_t seed, int size);

  int size() const { return size_; }
  int levels() const { return static_cast<int>(offsets_.size()); }
  // Texel (x, y) of mip level `level`, wrapped.
  uint8_t texel(int level, int x, int y) const {
    const int mask = (size_ >> level) - 1;
    return data_[offsets_[level] + static_cast<size_t>((y & mask) * (mask + 2) + (x & mask))];
  }

  // Trilinear samples, times `scale`, at n points (u, v) (n a multiple of 4) in level-0 texel
  // coordinates (texel centres at integer + 0.5; wrapping), sharing the level of detail
  // lod = log2(texels per pixel). Lods within 0.3 of an integer use one bilinear level
  // ("brilinear"): half the cost, no visible aliasing.
  void sample(const float* u, const float* v, int n, float lod, float scale, float* out) const {
    const int last = levels() - 1;
    const int level = lod <= 0.0f ? 0 : std::min(static_cast<int>(lod), last);
    const float f = lod <= 0.0f || level == last ? 0.0f : lod - static_cast<float>(level);
    if (f <= 0.3f || f >= 0.7f) {
      const Level l = view(f <= 0.3f ? level : level + 1);
      for (int i = 0; i < n; i += 4) {
        simd::store(out + i, l.bilinear4(simd::load(u + i), simd::load(v + i)) * scale);
      }
      return;
    }
    const Level l0 = view(level), l1 = view(level + 1);
    const float w1 = (f - 0.3f) * 2.5f * scale, w0 = scale - w1;
    // Two passes: one bilinear level per loop keeps everything in the 16 SSE registers
    // (interleaving both levels spills and runs twice as slow).
    for (int i = 0; i < n; i += 4) {
      simd::store(out + i, l0.bilinear4(simd::load(u + i), simd::load(v + i)) * w0);
    }
    for (int i = 0; i < n; i += 4) {
      simd::store(out + i,
                  simd::load(out + i) + l1.bilinear4(simd::load(u + i), simd::load(v + i)) * w1);
    }
  }

  // One trilinear sample.
  float sample(float u, float v, float lod) const {
    alignas(16) float u4[4] = {u, u, u, u}, v4[4] = {v, v, v, v}, out[4];
    sample(u4, v4, 4, lod, 1.0f, out);
    return out[0];
  }

 private:
  // One mip level, for bilinear sampling.
  struct Level {
    const uint8_t* texels;
    int shift;    // log2 of the level size n
    float scale;  // level-0 texel coordinates -> this level's

    simd::v4f bilinear4(const simd::v4f& u, const simd::v4f& v) const {
      using simd::v4f;
      using simd::v4i;
      const v4f x = u * scale - 0.5f, y = v * scale - 0.5f;
      const v4i xi = simd::floor_to_int(x), yi = simd::floor_to_int(y);
      const v4f fx = x - simd::to_float(xi), fy = y - simd::to_float(yi);
      const int mask = (1 << shift) - 1;
      const v4i xw = xi & mask, yw = yi & mask;
      const v4i index = (yw << shift) + yw + xw;  // row stride n + 1
      // One 16-bit load reads a texel and its right neighbour (rows carry a wrapped copy of
      // their first texel, and the level an extra copy of its first row).
      // Written out (no loop) so that even -O2 keeps it in registers.
      const auto pairs = [&index](const uint8_t* row) {
        uint16_t q0, q1, q2, q3;
        std::memcpy(&q0, row + index[0], 2);
        std::memcpy(&q1, row + index[1], 2);
        std::memcpy(&q2, row + index[2], 2);
        std::memcpy(&q3, row + index[3], 2);
        return v4i{q0, q1, q2, q3};
      };
      const v4i upper = pairs(texels), lower = pairs(texels + mask + 2);
      const v4f a = simd::to_float(upper & 255), b = simd::to_float(upper >> 8);
      const v4f c = simd::to_float(lower & 255), d = simd::to_float(lower >> 8);
      const v4f top = a + fx * (b - a), bottom = c + fx * (d - c);
      return top + fy * (bottom - top);
    }
  };
  Level view(int level) const {
    return {data_.data() + offsets_[level], log2_size_ - level,
            1.0f / static_cast<float>(1 << level)};
  }

  int size_;
  int log2_size_;
  // All levels back to back. Level l (n = size >> l) is (n + 1) rows of n + 1 texels: column
  // n and row n repeat column 0 and row 0, so bilinear neighbours never need wrapping.
  std::vector<uint8_t> data_;
  std::vector<size_t> offsets_;  // start of each level; level l is (size >> l)^2, row-major
};

// Level-0 texels of a texture kind, size*size row-major, values 0..255.
std::vector<uint8_t> generate_texture(TextureKind kind, uint32_t seed, int size);

}  // namespace hs::sim
