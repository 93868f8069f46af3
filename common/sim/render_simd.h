#pragma once
// Portable 4-wide float/int vectors for the renderer's inner loops, via the GCC/Clang vector
// extension: SSE2 on x86-64, NEON on ARM, no -march flags needed.
#include <cmath>
#include <cstdint>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#elif defined(__aarch64__)
#include <arm_neon.h>
#endif

namespace hs::sim::simd {

typedef float v4f __attribute__((vector_size(16)));
typedef int32_t v4i __attribute__((vector_size(16)));

inline v4f load(const float* p) {
  v4f v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline v4i load(const int32_t* p) {
  v4i v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store(float* p, const v4f& v) {
  std::memcpy(p, &v, sizeof v);
}
inline void store(int32_t* p, const v4i& v) {
  std::memcpy(p, &v, sizeof v);
}

inline v4f to_float(const v4i& v) {
  return __builtin_convertvector(v, v4f);
}
// Rounds towards minus infinity (conversion truncates; comparison masks are -1 where true).
inline v4i floor_to_int(const v4f& x) {
  const v4i i = __builtin_convertvector(x, v4i);
  return i + (x < to_float(i));
}
inline v4f max(const v4f& a, const v4f& b) {
  return a > b ? a : b;
}
// Square root: the baseline SIMD instruction of x86-64 (SSE2) or AArch64 (NEON).
inline v4f sqrt(const v4f& a) {
#if defined(__SSE2__)
  return reinterpret_cast<v4f>(_mm_sqrt_ps(reinterpret_cast<__m128>(a)));
#elif defined(__aarch64__)
  return reinterpret_cast<v4f>(vsqrtq_f32(reinterpret_cast<float32x4_t>(a)));
#else
  return v4f{std::sqrt(a[0]), std::sqrt(a[1]), std::sqrt(a[2]), std::sqrt(a[3])};
#endif
}
inline float horizontal_max(const v4f& v) {
  const float a = v[0] > v[1] ? v[0] : v[1];
  const float b = v[2] > v[3] ? v[2] : v[3];
  return a > b ? a : b;
}

}  // namespace hs::sim::simd
