// Software prefetch for the loops that stream particle data (docs/performance.md, *Prefetching
// the stencil records*): on the machine they were measured on, the hardware's own prefetching
// left those loops waiting for each group's data. Hints only: no effect on any result; a no-op
// for compilers without __builtin_prefetch.
#pragma once

// Always inlined: left to itself, GCC 12 lost every prefetch of two AVX2 loops (the particle
// check, the stress update) that called these plain inline functions.
#if defined(__GNUC__)
#define GIMP_PREFETCH_INLINE inline __attribute__((always_inline))
#else
#define GIMP_PREFETCH_INLINE inline
#endif

namespace gimp::prefetch {

/// How many groups of four particles ahead the loops ask for their data.
constexpr long kAheadGroups = 8;
constexpr long kAheadParticles = 4 * kAheadGroups;

/// Asks for the cache line holding p (Write: with the intent to write it).
template <bool Write = false> GIMP_PREFETCH_INLINE void line(const void *p) {
#if defined(__GNUC__)
  __builtin_prefetch(p, Write ? 1 : 0, 3);
#else
  (void)p;
#endif
}

/// Every line of the Bytes bytes from p: at 64-byte steps from the first byte and the line of the
/// last (p need not start a line). Unrolled: no loop is left per call.
template <long Bytes, bool Write = false> GIMP_PREFETCH_INLINE void span(const void *p) {
  const char *r = static_cast<const char *>(p);
  for (long b = 0; b < Bytes; b += 64)
    line<Write>(r + b);
  line<Write>(r + Bytes - 1);
}

/// A particle field for fields(): D doubles per particle from a.
template <int D> struct Field { const double *a; };

/// The entries of particles k .. k+3 of f (32 D bytes).
template <int D> GIMP_PREFETCH_INLINE void field(long k, Field<D> f) {
  span<32 * D>(f.a + static_cast<long>(D) * k);
}

/// The fields' entries of the four particles kAheadParticles after k, if there are n.
template <class... F> GIMP_PREFETCH_INLINE void fields(long k, long n, F... f) {
  if (k + kAheadParticles + 4 > n) return;
  (field(k + kAheadParticles, f), ...);
}

} // namespace gimp::prefetch
