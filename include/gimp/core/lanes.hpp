// Four doubles in one 256-bit register (AVX2) for the 2D kernels that run four particles at a
// time (transfer/lane_loops.hpp, GridT::blockRun): the shuffles they share. Every helper here is
// compiled for AVX2 whatever the build's flags, so it may be called only from functions that are
// too (GIMP_LANES), and those only where transfer::laneLoops::available() is true. The target
// includes FMA: the lane loop files are built with contraction (CMakeLists.txt), so their
// products and sums fuse where the compiler finds them, and round differently from the scalar
// kernels (at round-off; tests/check_lanes.py). Files built without contraction (the stencils'
// lanes) round as the scalar code does.
#pragma once

// GCC and Clang only: the build sets contraction per file for them (-ffp-contract=off, =fast for
// the lane loops); other compilers that define __GNUC__ run the scalar code.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__INTEL_LLVM_COMPILER) &&                 \
    !defined(__NVCOMPILER) && !defined(__INTEL_COMPILER)
#define GIMP_HAVE_LANES 1
#include <immintrin.h>

#define GIMP_LANES __attribute__((target("avx2,fma")))
#define GIMP_LANES_INLINE inline __attribute__((target("avx2,fma"), always_inline))
// A lambda's call operator is a function of its own: one that uses lanes says so after its
// parameter list, [&](int k) GIMP_LANES_LAMBDA { ... }.
#define GIMP_LANES_LAMBDA __attribute__((target("avx2,fma"), always_inline))

namespace gimp::lanes {

using V4 = __m256d;

/// Rows r0..r3 (four doubles each) as columns: c[i] = (r0[i], r1[i], r2[i], r3[i]).
GIMP_LANES_INLINE void transpose(V4 r0, V4 r1, V4 r2, V4 r3, V4 *c) {
  const V4 t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);
  const V4 t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
  c[0] = _mm256_permute2f128_pd(t0, t2, 0x20);
  c[1] = _mm256_permute2f128_pd(t1, t3, 0x20);
  c[2] = _mm256_permute2f128_pd(t0, t2, 0x31);
  c[3] = _mm256_permute2f128_pd(t1, t3, 0x31);
}

/// The four 2-vectors at p (x, y, x, y, ...) as their x and y in lanes.
GIMP_LANES_INLINE void loadXY(const double *p, V4 &X, V4 &Y) {
  const V4 u = _mm256_loadu2_m128d(p + 4, p), w = _mm256_loadu2_m128d(p + 6, p + 2);
  X = _mm256_unpacklo_pd(u, w);
  Y = _mm256_unpackhi_pd(u, w);
}

/// The inverse of loadXY.
GIMP_LANES_INLINE void storeXY(double *p, V4 X, V4 Y) {
  const V4 lo = _mm256_unpacklo_pd(X, Y), hi = _mm256_unpackhi_pd(X, Y);
  _mm256_storeu2_m128d(p + 4, p, lo);
  _mm256_storeu2_m128d(p + 6, p + 2, hi);
}

/// (a, b, c) in lanes 0-2, lane 3 zero: a blend with a zero the compiler cannot see through. Its
/// own form of _mm256_set_pd(0, c, b, a) zeroes the upper half with a register-to-register vmovq,
/// which valgrind 3.19 cannot decode; the 3D kernels are counted under callgrind
/// (bench/multirate_counts.py, bench/kernel_counts.py).
GIMP_LANES_INLINE V4 set3(double a, double b, double c) {
  V4 z = _mm256_setzero_pd();
  __asm__("" : "+x"(z));
  return _mm256_blend_pd(_mm256_set_pd(c, c, b, a), z, 0b1000);
}

/// The three doubles at p in lanes 0-2, lane 3 zero (two loads and a blend: no shuffle): a 3D
/// point, or a node's three components.
GIMP_LANES_INLINE V4 load3(const double *p) {
  return _mm256_blend_pd(_mm256_zextpd128_pd256(_mm_loadu_pd(p)), _mm256_broadcast_sd(p + 2),
                         0b0100);
}

} // namespace gimp::lanes

#else
#define GIMP_HAVE_LANES 0
#endif
