// The pieces the 3D lane loops share (src/transfer/lane_loops3.cpp, lane_loops3_stress.cpp;
// transfer/lane_loops3.hpp): a node's or a particle's three components in lanes 0-2 of one AVX2
// register (lane 3 zero, never stored), a 3 x 3 tensor's columns, and the walks over a block's
// rows of reached nodes and over a particle's row entries.
#pragma once

#include "gimp/grid/stencils.hpp"

#include "gimp/core/lanes.hpp"
#include "gimp/core/prefetch.hpp"

#if GIMP_HAVE_LANES

namespace gimp::transfer::laneLoops {

// File-local to each loop file that includes this header.
namespace {

using lanes::V4;

GIMP_LANES_INLINE V4 splat(double a) {
  return _mm256_set1_pd(a);
}

using lanes::load3;

/// Lanes 0-2 of v to p (p[3] untouched).
GIMP_LANES_INLINE void store3(double *p, V4 v) {
  _mm_storeu_pd(p, _mm256_castpd256_pd128(v));
  _mm_store_sd(p + 2, _mm256_extractf128_pd(v, 1));
}

/// Column a of a row-major 3 x 3 tensor in lanes 0-2.
template <class T> GIMP_LANES_INLINE V4 column(const T &t, int a) {
  return lanes::set3(t(0, a), t(1, a), t(2, a));
}

/// Columns c[0..2] back into the row-major tensor t.
template <class T> GIMP_LANES_INLINE void setColumns(const V4 *c, T &t) {
  alignas(32) double a[3][4];
  for (int q = 0; q < 3; ++q)
    _mm256_store_pd(a[q], c[q]);
  for (int r = 0; r < 3; ++r)
    for (int q = 0; q < 3; ++q)
      t(r, q) = a[q][r];
}

/// The number of nodes the block reaches along each axis (Stencils::forEach).
GIMP_LANES_INLINE void reached(const Block<3> &b, int *nn) {
  for (int d = 0; d < 3; ++d)
    nn[d] = b.g[d][2] > 0.0 ? 3 : 2;
}

/// A row of a block's three nodes along x is 9 contiguous doubles (node i's component c at 3 i +
/// c), which two registers and a double hold: (x0 y0 z0 x1 | y1 z1 x2 y2 | z2). Per-node factors
/// f_0..2 spread onto that layout as (f0 f0 f0 f1 | f1 f1 f2 f2 | f2) (RowFactors, once per
/// particle), a node vector v (lanes 0-2) as (vx vy vz vx | vy vz vx vy | vz) (Spread: once per
/// particle where each row's vector is a multiple of the particle's, as in FLIP's P2G; once per
/// row otherwise), so that adding f_i v to the three nodes is two loads, two stores and a
/// double.
struct RowFactors {
  V4 a, b;
  double c;
};
GIMP_LANES_INLINE RowFactors rowFactors(const double *f) {
  return {_mm256_set_pd(f[1], f[0], f[0], f[0]), _mm256_set_pd(f[2], f[2], f[1], f[1]), f[2]};
}
struct Spread {
  V4 a, b;
  double c;
};
GIMP_LANES_INLINE Spread spread(V4 v) {
  return {_mm256_permute4x64_pd(v, _MM_SHUFFLE(0, 2, 1, 0)),
          _mm256_permute4x64_pd(v, _MM_SHUFFLE(1, 0, 2, 1)),
          _mm_cvtsd_f64(_mm256_extractf128_pd(v, 1))};
}
GIMP_LANES_INLINE Spread operator*(double s, const Spread &v) {
  const V4 S = _mm256_set1_pd(s);
  return {S * v.a, S * v.b, s * v.c};
}
/// Node i of the row at p gets f_i v (i = 0, 1, 2).
GIMP_LANES_INLINE void addToRow(double *p, const RowFactors &f, const Spread &v) {
  _mm256_storeu_pd(p, _mm256_loadu_pd(p) + f.a * v.a);
  _mm256_storeu_pd(p + 4, _mm256_loadu_pd(p + 4) + f.b * v.b);
  p[8] += f.c * v.c;
}
/// Node i of the row at p gets f_i v + g_i u.
GIMP_LANES_INLINE void addToRow(double *p, const RowFactors &f, const Spread &v,
                                const RowFactors &g, const Spread &u) {
  _mm256_storeu_pd(p, _mm256_loadu_pd(p) + f.a * v.a + g.a * u.a);
  _mm256_storeu_pd(p + 4, _mm256_loadu_pd(p + 4) + f.b * v.b + g.b * u.b);
  p[8] = p[8] + f.c * v.c + g.c * u.c;
}

/// f(first slot, w_j w_q, nn[0]) for each row along x of the nodes a block reaches (q, then j):
/// the tensor-product walk of the kernels that need the weights only.
template <class F> GIMP_LANES_INLINE void forBlockRows(const Block<3> &b, F &&f) {
  int nn[3];
  reached(b, nn);
  for (int q = 0; q < nn[2]; ++q)
    for (int j = 0; j < nn[1]; ++j)
      f(b.base + j * b.stride[0] + q * b.stride[1], b.w[1][j] * b.w[2][q], nn[0]);
}

/// Asks for the stencil record (its block, or its first level block) of the particle kAhead3
/// after k, if there are n: the records stream through each loop at 168 bytes or more a particle
/// (docs/performance.md, *Prefetching the stencil records in 3D*).
constexpr PetscInt kAhead3 = 8;
GIMP_LANES_INLINE void prefetchRecord(const Stencils<3> &st, PetscInt k, PetscInt n) {
  const PetscInt a = k + kAhead3;
  if (a >= n) return;
  if (st.isBlock(a)) return prefetch::span<sizeof(Block<3>)>(st.blocks.data() + st.blockOf[a]);
  if (st.isLevels(a)) prefetch::span<sizeof(LevelBlock<3>)>(st.levelBlocks.data() + st.levelOf[a]);
}

/// f(slot, weight, gradient) for every row entry of particle k (Stencils::forEach of a particle
/// that keeps rows), in a function the lane lambdas can be inlined into.
/// forRows of a particle that keeps level blocks, out of line (Stencils::forEachLevelNode).
template <class F> GIMP_LANES_INLINE void forLevelRows(const Stencils<3> &st, PetscInt k, F &f) {
  Stencils<3>::LevelRow r;
  for (Stencils<3>::LevelRows rows = st.levelRows(k); rows.next(r);)
    for (int i = 0; i < 4; ++i)
      if ((r.nodes >> i) & 1u) { // (levelNode's products: it cannot inline the lane lambdas)
        Vector<3> gr;
        gr[0] = r.g0[i] * r.wyz;
        gr[1] = r.w0[i] * r.gy;
        gr[2] = r.w0[i] * r.gz;
        f(r.slot + i, r.w0[i] * r.wyz, gr);
      }
}

template <class F> GIMP_LANES_INLINE void forRows(const Stencils<3> &st, PetscInt k, F &&f) {
  if (st.isLevels(k)) return forLevelRows(st, k, f);
  for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e)
    f(st.node[e], st.weight(e), st.gradient(e));
}

} // namespace

} // namespace gimp::transfer::laneLoops

#endif
