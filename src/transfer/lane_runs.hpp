// Runs of four 2D block particles in lanes (AVX2), the pieces every lane loop shares
// (src/transfer/lane_loops.cpp, src/transfer/lane_loops_stress.cpp; transfer/lane_loops.hpp): the
// loads and stores of particle fields four at a time, a lane group's blocks (Run, loadRun), the
// walk over the lane groups (forGroups) and the scatter of a run's contributions to its nodes,
// in particle order (addToNodes) or, for a run of one block, each node's four summed first
// (addSummed, byBlock). Every lane expression is the scalar one of transfer/block_kernels.hpp in
// the same order (see lane_loops.cpp), but for addSummed's sums.
#pragma once

#include "gimp/grid/stencils.hpp"

#include <cstddef>
#include <cstring>
#include <type_traits>

#include "gimp/core/lanes.hpp"

#if GIMP_HAVE_LANES

namespace gimp::transfer::laneLoops {

// File-local to each loop file that includes this header, as when the loops were one file: with
// external linkage GCC 12 drops the lane-group prefetch of forGroups (Stencils::prefetchGroup)
// from the internal force, P2G and G2P loops, and the internal force runs some 8 % slower.
namespace {

using lanes::transpose;
using lanes::V4;
using prefetch::Field;

GIMP_LANES_INLINE V4 splat(double a) {
  return _mm256_set1_pd(a);
}

/// The four row-major 2 x 2 tensors at a + 4 k .. as their entries xx, xy, yx, yy in lanes.
GIMP_LANES_INLINE void loadTensors(const double *a, PetscInt k, V4 *c) {
  const double *p = a + 4 * k;
  transpose(_mm256_loadu_pd(p), _mm256_loadu_pd(p + 4), _mm256_loadu_pd(p + 8),
            _mm256_loadu_pd(p + 12), c);
}
GIMP_LANES_INLINE void storeTensors(double *a, PetscInt k, const V4 *c) {
  V4 r[4];
  transpose(c[0], c[1], c[2], c[3], r);
  double *p = a + 4 * k;
  for (int q = 0; q < 4; ++q)
    _mm256_storeu_pd(p + 4 * q, r[q]);
}

/// The four symmetric stresses at a + 3 k .. (kStress<2> entries each: xx, yy, xy) as the entries
/// xx, xy, yx, yy of loadTensors, and back (xy from c[1]).
GIMP_LANES_INLINE void loadStress(const double *a, PetscInt k, V4 *c) {
  const double *p = a + 3 * k;
  c[0] = _mm256_set_pd(p[9], p[6], p[3], p[0]);
  c[3] = _mm256_set_pd(p[10], p[7], p[4], p[1]);
  c[1] = c[2] = _mm256_set_pd(p[11], p[8], p[5], p[2]);
}
GIMP_LANES_INLINE void storeStress(double *a, PetscInt k, const V4 *c) {
  alignas(32) double t[3][4];
  _mm256_store_pd(t[0], c[0]);
  _mm256_store_pd(t[1], c[3]);
  _mm256_store_pd(t[2], c[1]);
  double *p = a + 3 * k;
  for (int q = 0; q < 4; ++q)
    for (int e = 0; e < 3; ++e)
      p[3 * q + e] = t[e][q];
}

/// The four 2-vectors at a + 2 k .. as their x and y in lanes, and back.
GIMP_LANES_INLINE void loadVectors(const double *a, PetscInt k, V4 &X, V4 &Y) {
  lanes::loadXY(a + 2 * k, X, Y);
}
GIMP_LANES_INLINE void storeVectors(double *a, PetscInt k, V4 X, V4 Y) {
  lanes::storeXY(a + 2 * k, X, Y);
}

/// The nodal pairs at the same offset o from four row pointers, as x and y in lanes. With One
/// the four rows are one (a run of one block, byBlock): each component is one broadcast load.
template <bool One = false>
GIMP_LANES_INLINE void gatherPairs(const double *const *r, PetscInt o, V4 &X, V4 &Y) {
  if constexpr (One) {
    X = _mm256_broadcast_sd(r[0] + o);
    Y = _mm256_broadcast_sd(r[0] + o + 1);
    return;
  }
  const V4 u = _mm256_loadu2_m128d(r[2] + o, r[0] + o), w = _mm256_loadu2_m128d(r[3] + o, r[1] + o);
  X = _mm256_unpacklo_pd(u, w);
  Y = _mm256_unpackhi_pd(u, w);
}

/// A run of four block particles (a lane group of the stencils): their 1D factors in lanes, the
/// first slot (times 2) of each particle's rows of nodes (BlockLocals::row) and the group's
/// pattern of block changes (bit q-1: particle q's block is not particle q-1's).
struct Run {
  V4 wx[3], wy[3], gx[3], gy[3];
  alignas(16) PetscInt row[3][4]; // row[j][q]: particle q's row j
  int split;
};

/// body(std::true_type{}) when the run's four particles share one block (no block changes,
/// split 0: one set of nodes, which each particle reaches at the same (j, i)), else
/// body(std::false_type{}): a kernel's body for either case, the first reading a node by one
/// broadcast load (gatherPairs<true>) and adding its four contributions at once (addSummed).
/// Lane groups take one block wherever the nodes allow (src/grid/stencil_lanes.cpp,
/// alignedStarts).
template <class Body> GIMP_LANES_INLINE void byBlock(const Run &R, Body &&body) {
  if (R.split == 0)
    body(std::true_type{});
  else
    body(std::false_type{});
}

/// Lane(k, group) for each lane group k .. k+3 of [k0, k1) (k0 a multiple of 4), one(k) for
/// every other particle, in particle order.
template <class Lane, class One>
GIMP_LANES_INLINE void forGroups(const Stencils<2> &st, PetscInt k0, PetscInt k1, Lane &&lane,
                                 One &&one) {
  PetscInt k = k0;
  for (; k % 4 != 0 && k < k1; ++k) // (callers start at a group)
    one(k);
  if (st.compact)
    for (; k + 4 <= k1; k += 4) {
      const std::uint8_t group = st.laneGroupOf(k / 4);
      if (group) {
        st.prefetchGroup(k / 4 + prefetch::kAheadGroups); // the record 8 groups on
        lane(k, group);
        continue;
      }
      for (int q = 0; q < 4; ++q)
        one(k + q);
    }
  for (; k < k1; ++k)
    one(k);
}

template <bool Slopes>
GIMP_LANES_INLINE void loadRun(const Stencils<2> &st, PetscInt k, std::uint8_t group, Run &R) {
  R.split = group & 7;
  // The group's blocks are factor-major (LaneBlocks): a factor of the four in one load.
  const unsigned char *r = st.laneBlocks(k / 4);
  const double *f = reinterpret_cast<const double *>(r + offsetof(LaneBlocks, f));
  for (int i = 0; i < 3; ++i) {
    R.wx[i] = _mm256_loadu_pd(f + 4 * i);
    R.wy[i] = _mm256_loadu_pd(f + 4 * (3 + i));
    if constexpr (Slopes) {
      R.gx[i] = _mm256_loadu_pd(f + 4 * (6 + i));
      R.gy[i] = _mm256_loadu_pd(f + 4 * (9 + i));
    }
  }
  if constexpr (sizeof(PetscInt) == 4) { // the rows' first slots, times 2, four at a time
    const __m128i base2 =
        _mm_slli_epi32(_mm_loadu_si128((const __m128i *)(r + offsetof(LaneBlocks, base))), 1);
    const __m128i step2 =
        _mm_slli_epi32(_mm_loadu_si128((const __m128i *)(r + offsetof(LaneBlocks, stride))), 1);
    const __m128i r1 = _mm_add_epi32(base2, step2);
    _mm_store_si128((__m128i *)R.row[0], base2);
    _mm_store_si128((__m128i *)R.row[1], r1);
    _mm_store_si128((__m128i *)R.row[2], _mm_add_epi32(r1, step2));
  } else {
    PetscInt base[4], stride[4];
    std::memcpy(base, r + offsetof(LaneBlocks, base), sizeof(base));
    std::memcpy(stride, r + offsetof(LaneBlocks, stride), sizeof(stride));
    for (int q = 0; q < 4; ++q)
      for (int j = 0; j < 3; ++j)
        R.row[j][q] = 2 * (base[q] + j * stride[q]);
  }
}

/// blocks::interpolate for a run: f_p = sum_j w_j sum_i w_i f_ij (x and y in lanes; fused
/// where the including file contracts). One: the run is one block (byBlock).
template <bool One = false>
GIMP_LANES_INLINE void interpolateRun(const Run &R, const double *fg, V4 &fx, V4 &fy) {
  fx = fy = splat(0);
  for (int j = 0; j < 3; ++j) {
    const double *r[4] = {fg + R.row[j][0], fg + R.row[j][1], fg + R.row[j][2], fg + R.row[j][3]};
    V4 gx, gy;
    gatherPairs<One>(r, 0, gx, gy);
    V4 tx = R.wx[0] * gx, ty = R.wx[0] * gy;
    for (int i = 1; i < 3; ++i) {
      gatherPairs<One>(r, 2 * i, gx, gy);
      tx = tx + R.wx[i] * gx;
      ty = ty + R.wx[i] * gy;
    }
    fx = fx + R.wy[j] * tx;
    fy = fy + R.wy[j] * ty;
  }
}

/// A run's contributions to its 3 x 3 nodes: pairs (X, Y) and masses M, four particles each.
struct NodeValues {
  V4 X[3][3], Y[3][3], M[3][3];
};

/// Lane q of pairs unpacked as lo = (0, 2), hi = (1, 3); lane q of M as the low double.
template <int Q> GIMP_LANES_INLINE __m128d pairOf(V4 lo, V4 hi) {
  if constexpr (Q == 0) return _mm256_castpd256_pd128(lo);
  if constexpr (Q == 1) return _mm256_castpd256_pd128(hi);
  if constexpr (Q == 2) return _mm256_extractf128_pd(lo, 1);
  if constexpr (Q == 3) return _mm256_extractf128_pd(hi, 1);
}
template <int Q> GIMP_LANES_INLINE __m128d scalarOf(V4 M) {
  const __m128d h = Q < 2 ? _mm256_castpd256_pd128(M) : _mm256_extractf128_pd(M, 1);
  return Q % 2 == 0 ? h : _mm_unpackhi_pd(h, h);
}

/// Particles Q0 .. Q1-1 of a run, which share one block: at each node, loaded once, their
/// contributions added in particle order, stored once.
template <int Q0, int Q1, bool Mass>
GIMP_LANES_INLINE void addSegment(const Run &R, const NodeValues &N, double *f, double *mass) {
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const V4 lo = _mm256_unpacklo_pd(N.X[j][i], N.Y[j][i]),
               hi = _mm256_unpackhi_pd(N.X[j][i], N.Y[j][i]);
      double *r = f + R.row[j][Q0] + 2 * i;
      __m128d a = _mm_loadu_pd(r);
      a = _mm_add_pd(a, pairOf<Q0>(lo, hi));
      if constexpr (Q0 + 1 < Q1) a = _mm_add_pd(a, pairOf<Q0 + 1>(lo, hi));
      if constexpr (Q0 + 2 < Q1) a = _mm_add_pd(a, pairOf<Q0 + 2>(lo, hi));
      if constexpr (Q0 + 3 < Q1) a = _mm_add_pd(a, pairOf<Q0 + 3>(lo, hi));
      _mm_storeu_pd(r, a);
      if constexpr (Mass) {
        double *s = mass + R.row[j][Q0] + 2 * i;
        __m128d b = _mm_add_sd(_mm_load_sd(s), scalarOf<Q0>(N.M[j][i]));
        if constexpr (Q0 + 1 < Q1) b = _mm_add_sd(b, scalarOf<Q0 + 1>(N.M[j][i]));
        if constexpr (Q0 + 2 < Q1) b = _mm_add_sd(b, scalarOf<Q0 + 2>(N.M[j][i]));
        if constexpr (Q0 + 3 < Q1) b = _mm_add_sd(b, scalarOf<Q0 + 3>(N.M[j][i]));
        _mm_store_sd(s, b);
      }
    }
}

/// The first particle after Q0 that starts a new block (bit q - 1 of Split set), or 4.
constexpr int segmentEnd(int split, int q0) {
  int q = q0 + 1;
  while (q < 4 && !((split >> (q - 1)) & 1))
    ++q;
  return q;
}
template <int Split, bool Mass, int Q0 = 0>
GIMP_LANES_INLINE void addSegments(const Run &R, const NodeValues &N, double *f, double *mass) {
  if constexpr (Q0 < 4) {
    constexpr int Q1 = segmentEnd(Split, Q0);
    addSegment<Q0, Q1, Mass>(R, N, f, mass);
    addSegments<Split, Mass, Q1>(R, N, f, mass);
  }
}

/// Adds a run's contributions to the nodes so that every node receives them in particle order,
/// as the scalar loop does (it adds particle k's to all its nodes, then particle k+1's): the run
/// is cut where a particle's block differs from the one before it, and each piece adds all its
/// nodes before the next (two particles with different blocks may reach one node at different
/// (j, i)). The common case, one block for all four, loads and stores each node once.
template <bool Mass>
GIMP_LANES_INLINE void addToNodes(const Run &R, const NodeValues &N, double *f, double *mass) {
  switch (R.split) {
  case 0:
    return addSegments<0, Mass>(R, N, f, mass);
  case 1:
    return addSegments<1, Mass>(R, N, f, mass);
  case 2:
    return addSegments<2, Mass>(R, N, f, mass);
  case 3:
    return addSegments<3, Mass>(R, N, f, mass);
  case 4:
    return addSegments<4, Mass>(R, N, f, mass);
  case 5:
    return addSegments<5, Mass>(R, N, f, mass);
  case 6:
    return addSegments<6, Mass>(R, N, f, mass);
  default:
    return addSegments<7, Mass>(R, N, f, mass);
  }
}

/// A run of one block (byBlock): each node's four contributions summed first, as (c0 + c1) +
/// (c2 + c3), then added to the node, two nodes of a row at once (their pairs are adjacent). Not
/// in particle order: the nodes' sums differ from the scalar loop's at round-off (APIC's
/// transfers and the force; FLIP's transfers keep addToNodes, the scalar loops bit for bit).
template <bool Mass>
GIMP_LANES_INLINE void addSummed(const Run &R, const NodeValues &N, double *f, double *mass) {
  for (int j = 0; j < 3; ++j) {
    double *r = f + R.row[j][0];
    // hadd(X, Y) = (x0 + x1, y0 + y1, x2 + x3, y2 + y3): the halves' sum is the node's pair
    const V4 s0 = _mm256_hadd_pd(N.X[j][0], N.Y[j][0]), s1 = _mm256_hadd_pd(N.X[j][1], N.Y[j][1]);
    const V4 s2 = _mm256_hadd_pd(N.X[j][2], N.Y[j][2]);
    const V4 p01 =
        _mm256_add_pd(_mm256_permute2f128_pd(s0, s1, 0x20), _mm256_permute2f128_pd(s0, s1, 0x31));
    const __m128d p2 = _mm_add_pd(_mm256_castpd256_pd128(s2), _mm256_extractf128_pd(s2, 1));
    _mm256_storeu_pd(r, _mm256_add_pd(_mm256_loadu_pd(r), p01));
    _mm_storeu_pd(r + 4, _mm_add_pd(_mm_loadu_pd(r + 4), p2));
    if constexpr (Mass) {
      double *s = mass + R.row[j][0];
      const V4 m01 = _mm256_hadd_pd(N.M[j][0], N.M[j][1]),
               m22 = _mm256_hadd_pd(N.M[j][2], N.M[j][2]);
      const __m128d m = _mm_add_pd(_mm256_castpd256_pd128(m01), _mm256_extractf128_pd(m01, 1));
      const __m128d m2 = _mm_add_sd(_mm256_castpd256_pd128(m22), _mm256_extractf128_pd(m22, 1));
      s[0] += _mm_cvtsd_f64(m);
      s[2] += _mm_cvtsd_f64(_mm_unpackhi_pd(m, m));
      s[4] += _mm_cvtsd_f64(m2);
    }
  }
}

} // namespace

} // namespace gimp::transfer::laneLoops

#endif
