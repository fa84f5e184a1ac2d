// Lanes of four 2D block particles (AVX2): see transfer/lane_loops.hpp. Every lane expression below
// is the scalar one of transfer/block_kernels.hpp (named next to it) in the same order; these
// functions have no FMA target and the build no floating-point contraction (-ffp-contract=off,
// which also holds in a build for a processor with FMA), so each lane rounds as the scalar code
// does.
#include "gimp/transfer/lane_loops.hpp"

#include "gimp/physics/deformation.hpp"
#include "gimp/physics/internal_force.hpp"
#include "gimp/physics/material.hpp"
#include "gimp/transfer/affine.hpp"
#include "gimp/transfer/transfer.hpp"

#include <cstddef>
#include <cstring>

#include "gimp/core/lanes.hpp"

namespace gimp::transfer::laneLoops {

#if GIMP_HAVE_LANES

bool available() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
}

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

/// The four 2-vectors at a + 2 k .. as their x and y in lanes, and back.
GIMP_LANES_INLINE void loadVectors(const double *a, PetscInt k, V4 &X, V4 &Y) {
  lanes::loadXY(a + 2 * k, X, Y);
}
GIMP_LANES_INLINE void storeVectors(double *a, PetscInt k, V4 X, V4 Y) {
  lanes::storeXY(a + 2 * k, X, Y);
}

/// The nodal pairs at the same offset o from four row pointers, as x and y in lanes.
GIMP_LANES_INLINE void gatherPairs(const double *const *r, PetscInt o, V4 &X, V4 &Y) {
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

/// blocks::offsets for a run: the offsets dx, dy of its node lines from the centres (XP, YP).
GIMP_LANES_INLINE void offsets(const Run &R, V4 XP, V4 YP, const double *xs, V4 *dx, V4 *dy) {
  for (int i = 0; i < 3; ++i) {
    const PetscInt o = 2 * i;
    dx[i] = _mm256_set_pd(xs[R.row[0][3] + o], xs[R.row[0][2] + o], xs[R.row[0][1] + o],
                          xs[R.row[0][0] + o]) -
            XP;
    dy[i] = _mm256_set_pd(xs[R.row[i][3] + 1], xs[R.row[i][2] + 1], xs[R.row[i][1] + 1],
                          xs[R.row[i][0] + 1]) -
            YP;
  }
}

/// blocks::offsetsAndInverseInertia (N = 3): the offsets dx, dy of the run's node lines from
/// the centres (XP, YP) and D^-1 (xx, xy, yx, yy), 0 where D is singular (inverseInertia2).
GIMP_LANES_INLINE void offsetsAndInverseInertia(const Run &R, V4 XP, V4 YP, const double *xs,
                                                V4 *dx, V4 *dy, V4 *Di) {
  offsets(R, XP, YP, xs, dx, dy);
  V4 S0x = splat(0), S1x = splat(0), S2x = splat(0), S0y = splat(0), S1y = splat(0), S2y = splat(0);
  for (int i = 0; i < 3; ++i) {
    const V4 tx = R.wx[i] * dx[i], ty = R.wy[i] * dy[i];
    S0x = S0x + R.wx[i];
    S0y = S0y + R.wy[i];
    S1x = S1x + tx;
    S1y = S1y + ty;
    S2x = S2x + tx * dx[i];
    S2y = S2y + ty * dy[i];
  }
  // inverseInertia2(a, b, b, d) with a = Sx2 Sy0, b = Sx1 Sy1, d = Sx0 Sy2
  const V4 a = S2x * S0y, b = S1x * S1y, d = S0x * S2y;
  const V4 det = a * d - b * b;
  const V4 half = splat(0.5) * (a + d);
  const V4 ok = _mm256_cmp_pd(det, splat(1e-12) * half * half, _CMP_GT_OQ);
  // (1 / det only where D is regular: no division by 0 in the other lanes, which -fp_trap would
  // stop on where the scalar code never divides)
  const V4 id = splat(1.0) / _mm256_blendv_pd(splat(1.0), det, ok);
  const V4 nb = _mm256_xor_pd(b, splat(-0.0));
  Di[0] = _mm256_and_pd(ok, d * id);
  Di[1] = _mm256_and_pd(ok, nb * id);
  Di[2] = _mm256_and_pd(ok, nb * id);
  Di[3] = _mm256_and_pd(ok, a * id);
}

/// product<2>(B, Di).
GIMP_LANES_INLINE void product(const V4 *B, const V4 *Di, V4 *C) {
  C[0] = B[0] * Di[0] + B[1] * Di[2];
  C[1] = B[0] * Di[1] + B[1] * Di[3];
  C[2] = B[2] * Di[0] + B[3] * Di[2];
  C[3] = B[2] * Di[1] + B[3] * Di[3];
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

/// blocks::affineScatter: node (i, j) gets m w_j [w_i (v + C e_y dy_j) + w_i dx_i C e_x] and, with
/// mass, m w_i w_j.
GIMP_LANES_INLINE void affineScatter(const Run &R, V4 mp, V4 VX, V4 VY, const V4 *C, const V4 *dx,
                                     const V4 *dy, double *mom, double *mass) {
  NodeValues N;
  V4 wdx[3];
  for (int i = 0; i < 3; ++i)
    wdx[i] = R.wx[i] * dx[i];
  for (int j = 0; j < 3; ++j) {
    const V4 mw = mp * R.wy[j];
    const V4 rx = mw * (VX + C[1] * dy[j]), ry = mw * (VY + C[3] * dy[j]);
    const V4 tx = mw * C[0], ty = mw * C[2];
    for (int i = 0; i < 3; ++i) {
      N.X[j][i] = R.wx[i] * rx + wdx[i] * tx;
      N.Y[j][i] = R.wx[i] * ry + wdx[i] * ty;
      N.M[j][i] = R.wx[i] * mw;
    }
  }
  if (mass)
    addToNodes<true>(R, N, mom, mass);
  else
    addToNodes<false>(R, N, mom, nullptr);
}

} // namespace

GIMP_LANES void particlesToGridAffineB(const Stencils<2> &st, PetscInt n, const double *m,
                                       const double *v, const double *B, const double *xc,
                                       const double *xs, double *mom, double *mass) {
  const auto lane = [&](PetscInt k, std::uint8_t group) GIMP_LANES_LAMBDA {
    prefetch::fields(k, n, Field<2>{xc}, Field<2>{v}, Field<4>{B}, Field<1>{m});
    Run R;
    loadRun<false>(st, k, group, R);
    V4 XP, YP, VX, VY, Bk[4], Di[4], C[4], dx[3], dy[3];
    loadVectors(xc, k, XP, YP);
    loadVectors(v, k, VX, VY);
    loadTensors(B, k, Bk);
    offsetsAndInverseInertia(R, XP, YP, xs, dx, dy, Di);
    product(Bk, Di, C);
    affineScatter(R, _mm256_loadu_pd(m + k), VX, VY, C, dx, dy, mom, mass);
  };
  forGroups(st, 0, n, lane, [&](PetscInt k) {
    particleToGridAffineB<2>(st, k, m[k], v + 2 * k, tensorAt<2>(B, k), xc + 2 * k, xs, mom, mass);
  });
}

GIMP_LANES void internalForce(const Stencils<2> &st, PetscInt n, const double *V,
                              const double *stress, double *f) {
  const auto lane = [&](PetscInt k, std::uint8_t group) GIMP_LANES_LAMBDA {
    prefetch::fields(k, n, Field<4>{stress}, Field<1>{V});
    Run R;
    loadRun<true>(st, k, group, R);
    V4 S[4];
    loadTensors(stress, k, S);
    const V4 nV = _mm256_xor_pd(_mm256_loadu_pd(V + k), splat(-0.0));
    const V4 A00 = nV * S[0], A01 = nV * S[1], A10 = nV * S[2], A11 = nV * S[3];
    // blocks::internalForce: f_ij += g_i (A0 w_j) + w_i (A1 g_j), A0 = (A00, A10), A1 = (A01, A11)
    NodeValues N;
    for (int j = 0; j < 3; ++j) {
      const V4 ax = A00 * R.wy[j], ay = A10 * R.wy[j], cx = A01 * R.gy[j], cy = A11 * R.gy[j];
      for (int i = 0; i < 3; ++i) {
        N.X[j][i] = R.gx[i] * ax + R.wx[i] * cx;
        N.Y[j][i] = R.gx[i] * ay + R.wx[i] * cy;
      }
    }
    addToNodes<false>(R, N, f, nullptr);
  };
  forGroups(st, 0, n, lane,
            [&](PetscInt k) { physics::internalForce<2>(st, k, k + 1, V, stress, f); });
}

namespace {

/// blocks::affineGather for a run: v_p = sum_j w_j t_j, B0 = sum_j w_j u_j, B1 = sum_j (w_j dy_j)
/// t_j with t_j = sum_i w_i v_ij, u_j = sum_i (w_i v_ij) dx_i; B_p = (B0x, B1x; B0y, B1y).
GIMP_LANES_INLINE void affineGather(const Run &R, const double *vg, const V4 *dx, const V4 *dy,
                                    V4 &vx, V4 &vy, V4 *Bk) {
  V4 B0x = splat(0), B0y = splat(0), B1x = splat(0), B1y = splat(0);
  vx = splat(0);
  vy = splat(0);
  for (int j = 0; j < 3; ++j) {
    const double *r[4] = {vg + R.row[j][0], vg + R.row[j][1], vg + R.row[j][2], vg + R.row[j][3]};
    V4 tx, ty, ux, uy;
    for (int i = 0; i < 3; ++i) {
      V4 gx, gy;
      gatherPairs(r, 2 * i, gx, gy);
      const V4 wvx = R.wx[i] * gx, wvy = R.wx[i] * gy;
      if (i == 0) {
        tx = wvx;
        ty = wvy;
        ux = wvx * dx[0];
        uy = wvy * dx[0];
      } else {
        tx = tx + wvx;
        ty = ty + wvy;
        ux = ux + wvx * dx[i];
        uy = uy + wvy * dx[i];
      }
    }
    const V4 wdy = R.wy[j] * dy[j];
    vx = vx + R.wy[j] * tx;
    vy = vy + R.wy[j] * ty;
    B0x = B0x + R.wy[j] * ux;
    B0y = B0y + R.wy[j] * uy;
    B1x = B1x + wdy * tx;
    B1y = B1y + wdy * ty;
  }
  Bk[0] = B0x;
  Bk[1] = B1x;
  Bk[2] = B0y;
  Bk[3] = B1y;
}

/// APIC G2P of every particle, the move by dt v_p and, with Project, the re-projection of the
/// new affine momenta into mom (x may be xc: every centre of a run is read before it moves).
template <bool Project>
GIMP_LANES_INLINE void gridToParticlesAffineRuns(const Stencils<2> &st, PetscInt n,
                                                 const double *vg, const double *xc,
                                                 const double *xs, double dt, const double *m,
                                                 double *v, double *B, double *x, double *mom) {
  const auto one = [&](PetscInt k) {
    double vp[2];
    Tensor<2> Bk;
    if constexpr (Project)
      particleFromAndToGridAffine<2>(st, k, m[k], vg, xc + 2 * k, xs, vp, Bk, mom);
    else
      particleFromGridAffine<2>(st, k, vg, xc + 2 * k, xs, vp, Bk);
    tensorAt<2>(B, k) = Bk;
    for (int c = 0; c < 2; ++c) {
      v[2 * k + c] = vp[c];
      x[2 * k + c] += dt * vp[c];
    }
  };
  // With weights centred on the positions (x == xc) the centres read first are the positions
  // the run moves: neither fetched nor loaded twice.
  const bool centredOnX = x == xc;
  const auto lane = [&](PetscInt k, std::uint8_t group) GIMP_LANES_LAMBDA {
    if constexpr (Project)
      prefetch::fields(k, n, Field<2>{xc}, Field<1>{m}, Field<4>{B}, Field<2>{v});
    else
      prefetch::fields(k, n, Field<2>{xc}, Field<4>{B}, Field<2>{v});
    if (!centredOnX) prefetch::fields(k, n, Field<2>{x});
    Run R;
    loadRun<false>(st, k, group, R);
    V4 XP, YP, dx[3], dy[3], vx, vy, Bk[4];
    loadVectors(xc, k, XP, YP);
    if constexpr (Project) {
      V4 Di[4], C[4];
      offsetsAndInverseInertia(R, XP, YP, xs, dx, dy, Di);
      affineGather(R, vg, dx, dy, vx, vy, Bk);
      product(Bk, Di, C);
      affineScatter(R, _mm256_loadu_pd(m + k), vx, vy, C, dx, dy, mom, nullptr);
    } else {
      offsets(R, XP, YP, xs, dx, dy);
      affineGather(R, vg, dx, dy, vx, vy, Bk);
    }
    storeTensors(B, k, Bk);
    storeVectors(v, k, vx, vy);
    V4 X = XP, Y = YP;
    if (!centredOnX) loadVectors(x, k, X, Y);
    const V4 dtv = splat(dt);
    storeVectors(x, k, X + dtv * vx, Y + dtv * vy);
  };
  forGroups(st, 0, n, lane, one);
}

} // namespace

GIMP_LANES void gridToParticlesAffineProjected(const Stencils<2> &st, PetscInt n, const double *vg,
                                               const double *xc, const double *xs, double dt,
                                               const double *m, double *v, double *B, double *x,
                                               double *mom) {
  gridToParticlesAffineRuns<true>(st, n, vg, xc, xs, dt, m, v, B, x, mom);
}

GIMP_LANES void gridToParticlesAffine(const Stencils<2> &st, PetscInt n, const double *vg,
                                      const double *xc, const double *xs, double dt, double *v,
                                      double *B, double *x) {
  gridToParticlesAffineRuns<false>(st, n, vg, xc, xs, dt, nullptr, v, B, x, nullptr);
}

GIMP_LANES void velocityGradients(const Stencils<2> &st, PetscInt k0, PetscInt k1, const double *vg,
                                  double *L) {
  const auto lane = [&](PetscInt k, std::uint8_t group) GIMP_LANES_LAMBDA {
    Run R;
    loadRun<true>(st, k, group, R);
    // blocks::gradient: L0 = sum_j w_j sum_i g_i v_ij, L1 = sum_j g_j sum_i w_i v_ij
    V4 L0x = splat(0), L0y = splat(0), L1x = splat(0), L1y = splat(0);
    for (int j = 0; j < 3; ++j) {
      const double *r[4] = {vg + R.row[j][0], vg + R.row[j][1], vg + R.row[j][2], vg + R.row[j][3]};
      V4 px, py, sx, sy;
      for (int i = 0; i < 3; ++i) {
        V4 gx, gy;
        gatherPairs(r, 2 * i, gx, gy);
        if (i == 0) {
          px = R.gx[0] * gx;
          py = R.gx[0] * gy;
          sx = R.wx[0] * gx;
          sy = R.wx[0] * gy;
        } else {
          px = px + R.gx[i] * gx;
          py = py + R.gx[i] * gy;
          sx = sx + R.wx[i] * gx;
          sy = sy + R.wx[i] * gy;
        }
      }
      L0x = L0x + R.wy[j] * px;
      L0y = L0y + R.wy[j] * py;
      L1x = L1x + R.gy[j] * sx;
      L1y = L1y + R.gy[j] * sy;
    }
    const V4 Lk[4] = {L0x, L1x, L0y, L1y};
    storeTensors(L, k - k0, Lk);
  };
  forGroups(st, k0, k1, lane,
            [&](PetscInt k) { tensorAt<2>(L, k - k0) = velocityGradientAt<2>(st, k, vg); });
}

GIMP_LANES void updateDeformation(const Scene<2> &sc, ParticleView<2> &p, const double *L,
                                  double dt, PetscInt k0, PetscInt k1) {
  const bool stretch = sc.tracking == Tracking::Stretch;
  const bool lanes = stretch || sc.tracking == Tracking::None;
  const V4 DT = splat(dt), HALF = splat(0.5), ONE = splat(1.0), ZERO = splat(0.0), TWO = splat(2.0),
           MTWO = splat(-2.0);
  PetscInt k = k0;
  while (lanes && k + 4 <= k1) {
    const Material &mat = sc.materialOf(p.id[k]);
    if (mat.model != MaterialModel::Linear || &sc.materialOf(p.id[k + 1]) != &mat ||
        &sc.materialOf(p.id[k + 2]) != &mat || &sc.materialOf(p.id[k + 3]) != &mat) {
      physics::updateDeformation(sc, p, L + 4 * (k - k0), dt, k, k + 1);
      ++k;
      continue;
    }
    prefetch::fields(k, p.n, Field<4>{p.F}, Field<4>{p.s}, Field<1>{p.V}, Field<1>{p.V0});
    if (mat.planeStrain) prefetch::fields(k, p.n, Field<1>{p.szz});
    if (stretch) prefetch::fields(k, p.n, Field<2>{p.l0}, Field<2>{p.l});
    V4 Lk[4], F[4], S[4];
    loadTensors(L, k - k0, Lk);
    loadTensors(p.F, k, F);
    // physics::updateDeformation: F += dt L F, entry (i, j) dt (L_i0 F_0j + L_i1 F_1j)
    const V4 Fn[4] = {
        F[0] + DT * (Lk[0] * F[0] + Lk[1] * F[2]), F[1] + DT * (Lk[0] * F[1] + Lk[1] * F[3]),
        F[2] + DT * (Lk[2] * F[0] + Lk[3] * F[2]), F[3] + DT * (Lk[2] * F[1] + Lk[3] * F[3])};
    storeTensors(p.F, k, Fn);
    _mm256_storeu_pd(p.V + k, (Fn[0] * Fn[3] - Fn[1] * Fn[2]) * _mm256_loadu_pd(p.V0 + k));
    // material::jaumannUpdate: D = (L + L^T) / 2, w = W_xy, the spin in closed form
    const V4 D00 = HALF * (Lk[0] + Lk[0]), D01 = HALF * (Lk[1] + Lk[2]),
             D10 = HALF * (Lk[2] + Lk[1]), D11 = HALF * (Lk[3] + Lk[3]);
    const V4 w = HALF * (Lk[1] - Lk[2]);
    const V4 tr = D00 + D11;
    loadTensors(p.s, k, S);
    const V4 a = TWO * w * S[1], b = w * (S[3] - S[0]), c = MTWO * w * S[1];
    const V4 lt = splat(mat.lambdaStar) * tr, mu2 = splat(2.0 * mat.mu);
    const V4 Sn[4] = {
        S[0] + DT * (lt * ONE + mu2 * D00 + a), S[1] + DT * (lt * ZERO + mu2 * D01 + b),
        S[2] + DT * (lt * ZERO + mu2 * D10 + b), S[3] + DT * (lt * ONE + mu2 * D11 + c)};
    storeTensors(p.s, k, Sn);
    if (mat.planeStrain)
      _mm256_storeu_pd(p.szz + k, _mm256_loadu_pd(p.szz + k) + DT * splat(mat.lambda) * tr);
    if (stretch) { // tracking::updateDomain: l_a = |F e_a| l0_a
      V4 L0x, L0y;
      loadVectors(p.l0, k, L0x, L0y);
      storeVectors(p.l, k, _mm256_sqrt_pd(Fn[0] * Fn[0] + Fn[2] * Fn[2]) * L0x,
                   _mm256_sqrt_pd(Fn[1] * Fn[1] + Fn[3] * Fn[3]) * L0y);
    }
    k += 4;
  }
  if (k < k1) physics::updateDeformation(sc, p, L + 4 * (k - k0), dt, k, k1);
}

GIMP_LANES PetscInt checkParticles(PetscInt n, const double *x, const double *l, const double *s,
                                   const double *V, const double *lo, const double *hi, double hmax,
                                   const double *own0, const double *own1, bool count,
                                   PetscInt &bad, PetscInt64 &leaving) {
  const PetscInt n4 = n / 4 * 4;
  const V4 lox = splat(lo[0]), loy = splat(lo[1]), hix = splat(hi[0]), hiy = splat(hi[1]),
           hm = splat(hmax), zero = splat(0.0), inf = splat(INFINITY), sign = splat(-0.0),
           o0x = splat(own0[0]), o0y = splat(own0[1]), o1x = splat(own1[0]), o1y = splat(own1[1]);
  bad = -1;
  for (PetscInt k = 0; k < n4; k += 4) {
    prefetch::fields(k, n, Field<2>{x}, Field<2>{l}, Field<4>{s}, Field<1>{V});
    V4 X, Y, LX, LY, S[4];
    loadVectors(x, k, X, Y);
    if (count) { // !(own0 <= x && x < own1), both axes
      const V4 in = _mm256_and_pd(
          _mm256_and_pd(_mm256_cmp_pd(o0x, X, _CMP_LE_OQ), _mm256_cmp_pd(o0y, Y, _CMP_LE_OQ)),
          _mm256_and_pd(_mm256_cmp_pd(X, o1x, _CMP_LT_OQ), _mm256_cmp_pd(Y, o1y, _CMP_LT_OQ)));
      leaving += 4 - __builtin_popcount(static_cast<unsigned>(_mm256_movemask_pd(in)));
    }
    if (bad >= 0) continue;
    loadVectors(l, k, LX, LY);
    loadTensors(s, k, S);
    const V4 sum = X + Y + (S[0] + S[3] + S[1]);
    V4 ok = _mm256_cmp_pd(_mm256_andnot_pd(sign, sum), inf, _CMP_LT_OQ); // finite
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(_mm256_loadu_pd(V + k), zero, _CMP_GT_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(lox, X - LX, _CMP_LE_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(loy, Y - LY, _CMP_LE_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(X + LX, hix, _CMP_LE_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(Y + LY, hiy, _CMP_LE_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(zero, LX, _CMP_LT_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(zero, LY, _CMP_LT_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(LX, hm, _CMP_LE_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(LY, hm, _CMP_LE_OQ));
    const unsigned fails = ~static_cast<unsigned>(_mm256_movemask_pd(ok)) & 15u;
    if (fails) bad = k + __builtin_ctz(fails);
  }
  return n4;
}

#else // no lanes on this architecture: the scalar loops

bool available() {
  return false;
}

void particlesToGridAffineB(const Stencils<2> &st, PetscInt n, const double *m, const double *v,
                            const double *B, const double *xc, const double *xs, double *mom,
                            double *mass) {
  transfer::particlesToGridAffineB<2>(st, n, m, v, B, xc, xs, mom, mass);
}
void internalForce(const Stencils<2> &st, PetscInt n, const double *V, const double *stress,
                   double *f) {
  physics::internalForce<2>(st, 0, n, V, stress, f);
}
void gridToParticlesAffineProjected(const Stencils<2> &st, PetscInt n, const double *vg,
                                    const double *xc, const double *xs, double dt, const double *m,
                                    double *v, double *B, double *x, double *mom) {
  transfer::gridToParticlesAffineProjected<2>(st, n, vg, xc, xs, dt, m, v, B, x, mom);
}
void gridToParticlesAffine(const Stencils<2> &st, PetscInt n, const double *vg, const double *xc,
                           const double *xs, double dt, double *v, double *B, double *x) {
  transfer::gridToParticlesAffine<2>(st, n, vg, xc, xs, dt, v, B, x);
}
void velocityGradients(const Stencils<2> &st, PetscInt k0, PetscInt k1, const double *vg,
                       double *L) {
  for (PetscInt k = k0; k < k1; ++k)
    tensorAt<2>(L, k - k0) = velocityGradientAt<2>(st, k, vg);
}
void updateDeformation(const Scene<2> &sc, ParticleView<2> &p, const double *L, double dt,
                       PetscInt k0, PetscInt k1) {
  physics::updateDeformation(sc, p, L, dt, k0, k1);
}
PetscInt checkParticles(PetscInt, const double *, const double *, const double *, const double *,
                        const double *, const double *, double, const double *, const double *,
                        bool, PetscInt &bad, PetscInt64 &) {
  bad = -1;
  return 0;
}

#endif

} // namespace gimp::transfer::laneLoops
