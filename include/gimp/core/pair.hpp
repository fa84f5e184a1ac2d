// Two doubles in one SSE2 register: the two components of a 2D nodal value (momentum, force,
// velocity) are stored next to each other in the window arrays, so the 2D block kernels load,
// scale, add and store both with one instruction each. Every operation is the scalar one applied
// to each lane in the same order (no fused multiply-add), so results are bit for bit those of the
// scalar loops they replace. SSE2 is part of every x86-64 processor; other targets get the same
// code from the compiler's generic vector lowering.
#pragma once

#include <cmath>
#include <cstring>
#include <type_traits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace gimp::simd {

using Pair = double __attribute__((vector_size(16)));

/// The two doubles at p (no alignment needed).
inline Pair load(const double *p) {
  Pair r;
  std::memcpy(&r, p, sizeof r);
  return r;
}
/// Store both lanes at p.
inline void store(double *p, Pair v) {
  std::memcpy(p, &v, sizeof v);
}
/// p += v, lane by lane.
inline void addTo(double *p, Pair v) {
  store(p, load(p) + v);
}
/// (a, a).
inline Pair splat(double a) {
  return Pair{a, a};
}
/// a in every lane of T (double or Pair).
template <class T> inline T broadcast(double a) {
  if constexpr (std::is_same_v<T, Pair>)
    return splat(a);
  else
    return a;
}

// The lane-by-lane operations below, for one double too (code written for T = double or Pair).
inline double minOf(double a, double b) {
  return a < b ? a : b;
}
inline double maxOf(double a, double b) {
  return a > b ? a : b;
}
inline double abs(double a) {
  return std::fabs(a);
}

/// Lane by lane std::min(b, a) and std::max(b, a): (a < b ? a : b) and (a > b ? a : b), a when
/// they compare equal or either is NaN, as the SSE2 instructions do.
inline Pair minOf(Pair a, Pair b) {
#if defined(__SSE2__)
  return _mm_min_pd(a, b);
#else
  return Pair{a[0] < b[0] ? a[0] : b[0], a[1] < b[1] ? a[1] : b[1]};
#endif
}
inline Pair maxOf(Pair a, Pair b) {
#if defined(__SSE2__)
  return _mm_max_pd(a, b);
#else
  return Pair{a[0] > b[0] ? a[0] : b[0], a[1] > b[1] ? a[1] : b[1]};
#endif
}
/// Lane by lane std::sqrt (correctly rounded either way).
inline Pair sqrt(Pair a) {
#if defined(__SSE2__)
  return _mm_sqrt_pd(a);
#else
  return Pair{std::sqrt(a[0]), std::sqrt(a[1])};
#endif
}
/// Lane by lane |a| (the sign bit cleared, as std::fabs).
inline Pair abs(Pair a) {
#if defined(__SSE2__)
  return _mm_andnot_pd(_mm_set1_pd(-0.0), a);
#else
  return Pair{a[0] < 0 ? -a[0] : a[0] == 0 ? 0.0 : a[0], a[1] < 0 ? -a[1] : a[1] == 0 ? 0.0 : a[1]};
#endif
}

/// a <= b and a < b in both lanes (false where either lane is NaN).
inline bool bothLe(Pair a, Pair b) {
#if defined(__SSE2__)
  return _mm_movemask_pd(_mm_cmple_pd(a, b)) == 3;
#else
  return a[0] <= b[0] && a[1] <= b[1];
#endif
}
inline bool bothLt(Pair a, Pair b) {
#if defined(__SSE2__)
  return _mm_movemask_pd(_mm_cmplt_pd(a, b)) == 3;
#else
  return a[0] < b[0] && a[1] < b[1];
#endif
}

} // namespace gimp::simd
