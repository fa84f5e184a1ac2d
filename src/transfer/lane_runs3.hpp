// The pieces the 3D lane loops share (src/transfer/lane_loops3.cpp, lane_loops3_stress.cpp;
// transfer/lane_loops3.hpp): a node's or a particle's three components in lanes 0-2 of one AVX2
// register (lane 3 zero, never stored), a 3 x 3 tensor's columns, and the walks over a block's
// rows of reached nodes and over a particle's row entries.
#pragma once

#include "gimp/grid/stencils.hpp"

#include "gimp/core/lanes.hpp"

#if GIMP_HAVE_LANES

namespace gimp::transfer::laneLoops {

// File-local to each loop file that includes this header.
namespace {

using lanes::V4;

GIMP_LANES_INLINE V4 splat(double a) {
  return _mm256_set1_pd(a);
}

/// The three doubles at p in lanes 0-2, lane 3 zero.
GIMP_LANES_INLINE V4 load3(const double *p) {
  return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p)), _mm_load_sd(p + 2), 1);
}

/// Lanes 0-2 of v to p (p[3] untouched).
GIMP_LANES_INLINE void store3(double *p, V4 v) {
  _mm_storeu_pd(p, _mm256_castpd256_pd128(v));
  _mm_store_sd(p + 2, _mm256_extractf128_pd(v, 1));
}

/// Column a of a row-major 3 x 3 tensor in lanes 0-2.
template <class T> GIMP_LANES_INLINE V4 column(const T &t, int a) {
  return _mm256_set_pd(0.0, t(2, a), t(1, a), t(0, a));
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

/// f(first slot, w_j w_q, nn[0]) for each row along x of the nodes a block reaches (q, then j):
/// the tensor-product walk of the kernels that need the weights only.
template <class F> GIMP_LANES_INLINE void forBlockRows(const Block<3> &b, F &&f) {
  int nn[3];
  reached(b, nn);
  for (int q = 0; q < nn[2]; ++q)
    for (int j = 0; j < nn[1]; ++j)
      f(b.base + j * b.stride[0] + q * b.stride[1], b.w[1][j] * b.w[2][q], nn[0]);
}

/// f(slot, weight, gradient) for every row entry of particle k (Stencils::forEach of a particle
/// that keeps rows), in a function the lane lambdas can be inlined into.
template <class F> GIMP_LANES_INLINE void forRows(const Stencils<3> &st, PetscInt k, F &&f) {
  for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e)
    f(st.node[e], st.weight(e), st.gradient(e));
}

} // namespace

} // namespace gimp::transfer::laneLoops

#endif
