// The stencils' block builders in lanes (AVX2, this file without contraction: their factors are
// setBlock's bit for bit): GridT<2>::blockRun, four 2D particles at a time, and
// GridT<3>::blockLanes, a 3D particle with its x, y and z in lanes. Grid::buildStencils
// (stencils.cpp) calls them first and falls back to its scalar path.
#include "gimp/core/lanes.hpp"
#include "gimp/grid/grid.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace gimp {

#if GIMP_HAVE_LANES
namespace {

using lanes::V4;

/// coarsestReaching for four particles (centres X, half-sizes Lh in lanes): the finest level
/// whose box holds every domain (0 if none), or -1 when some of the four are on a level and some
/// coarser (the run is not one).
GIMP_LANES_INLINE int laneLevel(const Grid<2> &grid, const V4 *X, const V4 *Lh) {
  for (int f = static_cast<int>(grid.levels.size()) - 1; f > 0; --f) {
    const BoxOf<2> &b = grid.levels[f].box;
    V4 in = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    for (int a = 0; a < 2; ++a) {
      in = _mm256_and_pd(in, _mm256_cmp_pd(X[a] - Lh[a], _mm256_set1_pd(b[a]), _CMP_GE_OQ));
      in = _mm256_and_pd(in, _mm256_cmp_pd(X[a] + Lh[a], _mm256_set1_pd(b[2 + a]), _CMP_LE_OQ));
    }
    const int mask = _mm256_movemask_pd(in);
    if (mask == 15) return f;
    if (mask != 0) return -1; // some of the four on level f, some coarser
  }
  return 0;
}

/// soleBlock's tests on level q for four particles in lanes, their first nodes in fi (as
/// doubles): whether each of the four has a 3-node block there that no finer level reaches.
GIMP_LANES_INLINE bool laneSoleBlocks(const Grid<2> &grid, const double *outwardReach, int q,
                                      const V4 *X, const V4 *Lh, V4 *fi) {
  const Level<2> &L = grid.levels[q];
  const V4 h = _mm256_set1_pd(L.h), ih = _mm256_set1_pd(L.ih), halfH = _mm256_set1_pd(0.5 * L.h);
  // soleBlock: the centre inside the box, l <= h / 2 (3 nodes), candidates [ir, i1] in the
  // window and at most 3 wide
  V4 ok = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  for (int a = 0; a < 2; ++a) {
    const V4 b0 = _mm256_set1_pd(L.box[a]), b1 = _mm256_set1_pd(L.box[2 + a]);
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(X[a], b0, _CMP_GE_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(X[a], b1, _CMP_LE_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(Lh[a], halfH, _CMP_LE_OQ));
    const V4 ir = _mm256_floor_pd((X[a] - Lh[a] - h - b0) * ih) + 1.0;
    const V4 i1 = _mm256_ceil_pd((X[a] + Lh[a] + h - b0) * ih) - 1.0;
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(ir, _mm256_set1_pd(L.w0[a]), _CMP_GE_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(ir + 2.0, _mm256_set1_pd(L.w1[a]), _CMP_LT_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(i1 - ir, _mm256_set1_pd(2.0), _CMP_LE_OQ));
    fi[a] = ir;
  }
  // no finer level reaches it (soleBlock's test, per level)
  for (int f = q + 1; f < static_cast<int>(grid.levels.size()); ++f) {
    const Level<2> &F = grid.levels[f];
    const V4 Z = _mm256_set1_pd(std::max(F.h, outwardReach[f]) + 0.5 * F.h);
    V4 misses = _mm256_setzero_pd();
    for (int a = 0; a < 2; ++a) {
      misses = _mm256_or_pd(misses,
                            _mm256_cmp_pd(X[a] + Lh[a] + Z, _mm256_set1_pd(F.box[a]), _CMP_LT_OQ));
      misses = _mm256_or_pd(
          misses, _mm256_cmp_pd(X[a] - Lh[a] - Z, _mm256_set1_pd(F.box[2 + a]), _CMP_GT_OQ));
    }
    ok = _mm256_and_pd(ok, misses);
  }
  return _mm256_movemask_pd(ok) == 15;
}

/// The window slots of level q's nodes fi (as doubles, four in lanes) into base.
GIMP_LANES_INLINE void laneSlots(const Grid<2> &grid, int q, const V4 *fi, PetscInt *base) {
  const Level<2> &L = grid.levels[q];
  if constexpr (sizeof(PetscInt) == 4) { // windowSlot, four at a time
    const __m128i ix = _mm256_cvttpd_epi32(fi[0]), iy = _mm256_cvttpd_epi32(fi[1]);
    const __m128i row =
        _mm_mullo_epi32(_mm_sub_epi32(iy, _mm_set1_epi32(L.w0[1])), _mm_set1_epi32(L.wn(0)));
    _mm_store_si128(reinterpret_cast<__m128i *>(base),
                    _mm_add_epi32(_mm_set1_epi32(L.offset),
                                  _mm_add_epi32(row, _mm_sub_epi32(ix, _mm_set1_epi32(L.w0[0])))));
  } else {
    alignas(16) int i0[2][4];
    _mm_store_si128(reinterpret_cast<__m128i *>(i0[0]), _mm256_cvttpd_epi32(fi[0]));
    _mm_store_si128(reinterpret_cast<__m128i *>(i0[1]), _mm256_cvttpd_epi32(fi[1]));
    for (int j = 0; j < 4; ++j) {
      const PetscInt c[2] = {i0[0][j], i0[1][j]};
      base[j] = grid.windowSlot(q, c);
    }
  }
}

/// shape::threeNodeWeights in lanes, each lane its arithmetic in its order: the weights w and
/// derivatives g of the three nodes from the particle's centre xi and half-size lam in cells.
GIMP_LANES_INLINE void laneThreeNodeWeights(V4 xi, V4 lam, V4 ih, V4 *w, V4 *g) {
  const V4 one = _mm256_set1_pd(1.0), zero = _mm256_setzero_pd(), half = _mm256_set1_pd(0.5);
  const V4 i2l = half / lam, i2lh = i2l * ih;
  const V4 A = xi - lam, B = xi + lam;
  const V4 bb = _mm256_min_pd(one, B), c = _mm256_max_pd(zero, B - 1.0);
  const V4 ua = 1.0 - A, ub = 1.0 - bb;
  w[0] = 0.5 * (ua - ub) * (ua + ub) * i2l;
  w[1] = (0.5 * (bb - A) * (bb + A) + c - 0.5 * c * c) * i2l;
  w[2] = 0.5 * c * c * i2l;
  g[0] = (ub - ua) * i2lh;
  g[1] = (1.0 - _mm256_andnot_pd(_mm256_set1_pd(-0.0), B - 1.0) - A) * i2lh;
  g[2] = c * i2lh;
}

/// setBlock's centres and half-sizes of four particles in cells of level L from nodes fi:
/// xi = (x - (box + i0 h)) / h, lam = l / h along each axis.
GIMP_LANES_INLINE void laneCells(const Level<2> &L, const V4 *X, const V4 *Lh, const V4 *fi, V4 *xi,
                                 V4 *lam) {
  const V4 h = _mm256_set1_pd(L.h), ih = _mm256_set1_pd(L.ih);
  for (int a = 0; a < 2; ++a) {
    xi[a] = (X[a] - (_mm256_set1_pd(L.box[a]) + fi[a] * h)) * ih;
    lam[a] = Lh[a] * ih;
  }
}

/// setBlock's factors of four particles in lanes: the weights w and derivatives g of their
/// 3-node blocks on level L (shape::threeNodeWeights per axis, from laneCells).
GIMP_LANES_INLINE void laneFactors(const Level<2> &L, const V4 *xi, const V4 *lam, V4 w[2][3],
                                   V4 g[2][3]) {
  const V4 ih = _mm256_set1_pd(L.ih);
  for (int a = 0; a < 2; ++a)
    laneThreeNodeWeights(xi[a], lam[a], ih, w[a], g[a]);
}

/// The smallest of four lanes, in every lane.
GIMP_LANES_INLINE V4 laneMin(V4 v) {
  const V4 t = _mm256_min_pd(v, _mm256_permute2f128_pd(v, v, 1));
  return _mm256_min_pd(t, _mm256_permute_pd(t, 0b0101));
}

/// One block for the four where the nodes allow it, so that the kernels take the group as one
/// piece (lane_runs.hpp, byBlock; a group whose blocks differ is cut where they change): along an
/// axis where the four blocks start at nodes m and m + 1 (fi), a block that starts at m + 1 and
/// whose third node carries nothing (c = 0 in threeNodeWeights: the domain ends in the block's
/// first cell, B = xi + lam <= 1 as laneThreeNodeWeights computes it from laneCells) may start at
/// m instead, with the factors (0, w0, w1): the same weights on the same nodes, node m's exactly
/// 0. Returns whether a block moves; late[a] marks the lanes that move along a, from[a] the first
/// nodes then.
GIMP_LANES_INLINE bool alignedStarts(const V4 *xi, const V4 *lam, const V4 *fi, V4 *late,
                                     V4 *from) {
  const V4 one = _mm256_set1_pd(1.0);
  bool moves = false;
  for (int a = 0; a < 2; ++a) {
    const V4 m = laneMin(fi[a]);
    const V4 B = xi[a] + lam[a];
    late[a] =
        _mm256_and_pd(_mm256_cmp_pd(fi[a], m + one, _CMP_EQ_OQ), _mm256_cmp_pd(B, one, _CMP_LE_OQ));
    const int lateMask = _mm256_movemask_pd(late[a]);
    if (lateMask == 0 ||
        (_mm256_movemask_pd(_mm256_cmp_pd(fi[a], m, _CMP_EQ_OQ)) | lateMask) != 15) {
      late[a] = _mm256_setzero_pd();
      from[a] = fi[a];
      continue;
    }
    from[a] = m;
    moves = true;
  }
  return moves;
}

/// The factors of the lanes late[a] moved one node on along a: (w0, w1, w2 = 0) -> (0, w0, w1).
GIMP_LANES_INLINE void moveFactors(const V4 *late, V4 w[2][3], V4 g[2][3]) {
  const V4 zero = _mm256_setzero_pd();
  for (int a = 0; a < 2; ++a) {
    w[a][2] = _mm256_blendv_pd(w[a][2], w[a][1], late[a]);
    w[a][1] = _mm256_blendv_pd(w[a][1], w[a][0], late[a]);
    w[a][0] = _mm256_blendv_pd(w[a][0], zero, late[a]);
    g[a][2] = _mm256_blendv_pd(g[a][2], g[a][1], late[a]);
    g[a][1] = _mm256_blendv_pd(g[a][1], g[a][0], late[a]);
    g[a][0] = _mm256_blendv_pd(g[a][0], zero, late[a]);
  }
}

/// Particles k .. k+3 as lane group k / 4 of s: their blocks (first slots base, row stride of
/// level L, factors w and g) stored factor-major.
GIMP_LANES_INLINE void storeLaneGroup(const Level<2> &L, PetscInt k, const PetscInt *base,
                                      const V4 w[2][3], const V4 g[2][3], Stencils<2> &s) {
  // The four blocks, factor-major in the room of four (LaneBlocks).
  std::uint8_t group = Stencils<2>::kLaneGroup;
  for (int j = 1; j < 4; ++j)
    if (base[j] != base[j - 1]) group |= static_cast<std::uint8_t>(1u << (j - 1));
  s.laneGroup[k / 4] = group;
  for (int j = 0; j < 4; ++j)
    s.blockOf[k + j] = (s.nBlocks + j) | Stencils<2>::kLaneBlock;
  s.nBlocks += 4;
  unsigned char *r = s.laneBlocks(k / 4);
  double *f = reinterpret_cast<double *>(r + offsetof(LaneBlocks, f));
  for (int i = 0; i < 3; ++i) {
    _mm256_storeu_pd(f + 4 * i, w[0][i]);
    _mm256_storeu_pd(f + 4 * (3 + i), w[1][i]);
    _mm256_storeu_pd(f + 4 * (6 + i), g[0][i]);
    _mm256_storeu_pd(f + 4 * (9 + i), g[1][i]);
  }
  const PetscInt stride[4] = {L.wn(0), L.wn(0), L.wn(0), L.wn(0)};
  std::memcpy(r + offsetof(LaneBlocks, base), base, 4 * sizeof(PetscInt));
  std::memcpy(r + offsetof(LaneBlocks, stride), stride, sizeof(stride));
}

/// GridT<2>::blockRun's particles of level q in lanes: soleBlock and setBlock for four particles,
/// each lane their scalar arithmetic in its order (no FMA: this function alone is compiled for
/// AVX2, and the build has no contraction).
GIMP_LANES bool blockRunLanes(const Grid<2> &grid, const std::uint8_t *threeNodeBlocks,
                              const double *outwardReach, PetscInt k, const double *x,
                              const double *l, Stencils<2> &s) {
  // The room this run's record will take 8 runs on is asked for now (a read prefetch; the line
  // then needs no fetch when it is written): the record's stores otherwise wait for its lines to
  // come from memory.
  if (const size_t ahead = static_cast<size_t>(s.nBlocks + 4 * prefetch::kAheadGroups);
      ahead + 4 <= s.blocks.size())
    prefetch::span<sizeof(LaneBlocks), true>(s.blocks.data() + ahead);
  prefetch::fields(k, static_cast<long>(s.start.size()) - 1, prefetch::Field<2>{x},
                   prefetch::Field<2>{l}); // (start has n + 1 entries)
  // x and y of the four particles (and of their half-sizes) in lanes
  V4 X[2], Lh[2];
  lanes::loadXY(x + 2 * k, X[0], X[1]);
  lanes::loadXY(l + 2 * k, Lh[0], Lh[1]);
  // coarsestReaching: the finest level whose box holds the particle's domain, the same for all
  // four (or the run is not one)
  const int q = laneLevel(grid, X, Lh);
  if (q < 0) return false;
  V4 fi[2];
  if (!laneSoleBlocks(grid, outwardReach, q, X, Lh, fi)) return false;
  // one block for the four where level q keeps a 3-node block from the new first nodes too
  V4 xi[2], lam[2], late[2], from[2];
  laneCells(grid.levels[q], X, Lh, fi, xi, lam);
  bool moves = alignedStarts(xi, lam, fi, late, from);
  alignas(16) PetscInt base[4];
  const auto regular = [&] {
    return threeNodeBlocks[base[0]] && threeNodeBlocks[base[1]] && threeNodeBlocks[base[2]] &&
           threeNodeBlocks[base[3]];
  };
  laneSlots(grid, q, moves ? from : fi, base);
  if (!regular()) {
    if (!moves) return false;
    moves = false;
    laneSlots(grid, q, fi, base);
    if (!regular()) return false;
  }
  V4 w[2][3], g[2][3];
  laneFactors(grid.levels[q], xi, lam, w, g);
  if (moves) moveFactors(late, w, g);
  storeLaneGroup(grid.levels[q], k, base, w, g, s);
  return true;
}

/// GridT<3>::blockLanes: soleBlock's tests and setBlock's factors with the three axes in lanes
/// 0-2, each lane the scalar arithmetic of its axis in its order (no FMA: this file has no
/// contraction). Lane 3 carries a half-size of one cell and is never used.
GIMP_LANES bool blockLanes3(const Grid<3> &grid, const std::uint8_t *threeNodeBlocks,
                            const double *outwardReach, int q, PetscInt k, const double *x,
                            const double *l, Stencils<3> &s) {
  const Level<3> &L = grid.levels[q];
  const V4 X = lanes::load3(x + 3 * k), Lh = lanes::load3(l + 3 * k);
  const V4 box0 = lanes::load3(&L.box[0]), box1 = lanes::load3(&L.box[3]);
  const V4 h = _mm256_set1_pd(L.h), ih = _mm256_set1_pd(L.ih);
  // soleBlock: the centre inside the box, l <= h / 2, candidates [ir, i1] in the window and at
  // most 3 wide
  V4 ok = _mm256_and_pd(_mm256_cmp_pd(X, box0, _CMP_GE_OQ), _mm256_cmp_pd(X, box1, _CMP_LE_OQ));
  ok = _mm256_and_pd(ok, _mm256_cmp_pd(Lh, _mm256_set1_pd(0.5 * L.h), _CMP_LE_OQ));
  const V4 ir = _mm256_floor_pd((X - Lh - h - box0) * ih) + 1.0;
  const V4 i1 = _mm256_ceil_pd((X + Lh + h - box0) * ih) - 1.0;
  const V4 w0 = lanes::set3(L.w0[0], L.w0[1], L.w0[2]);
  const V4 w1 = lanes::set3(L.w1[0], L.w1[1], L.w1[2]);
  ok = _mm256_and_pd(ok, _mm256_cmp_pd(ir, w0, _CMP_GE_OQ));
  ok = _mm256_and_pd(ok, _mm256_cmp_pd(ir + 2.0, w1, _CMP_LT_OQ));
  ok = _mm256_and_pd(ok, _mm256_cmp_pd(i1 - ir, _mm256_set1_pd(2.0), _CMP_LE_OQ));
  if ((_mm256_movemask_pd(ok) & 7) != 7) return false;
  alignas(16) int c[4];
  _mm_store_si128(reinterpret_cast<__m128i *>(c), _mm256_cvttpd_epi32(ir));
  const PetscInt i0[3] = {c[0], c[1], c[2]};
  const PetscInt base = grid.windowSlot(q, i0);
  if (!threeNodeBlocks[base]) return false;
  // no finer level reaches it (soleBlock's test, per level)
  for (int f = q + 1; f < static_cast<int>(grid.levels.size()); ++f) {
    const Level<3> &F = grid.levels[f];
    const V4 Z = _mm256_set1_pd(std::max(F.h, outwardReach[f]) + 0.5 * F.h);
    const V4 misses = _mm256_or_pd(_mm256_cmp_pd(X + Lh + Z, lanes::load3(&F.box[0]), _CMP_LT_OQ),
                                   _mm256_cmp_pd(X - Lh - Z, lanes::load3(&F.box[3]), _CMP_GT_OQ));
    if ((_mm256_movemask_pd(misses) & 7) == 0) return false;
  }
  // setBlock (lane 3's half-size one cell: no division by 0 there)
  V4 w[3], g[3], cw[4], cg[4];
  laneThreeNodeWeights((X - (box0 + ir * h)) * ih,
                       _mm256_blend_pd(Lh * ih, _mm256_set1_pd(1.0), 0b1000), ih, w, g);
  lanes::transpose(w[0], w[1], w[2], _mm256_setzero_pd(), cw); // cw[a]: axis a's three weights
  lanes::transpose(g[0], g[1], g[2], _mm256_setzero_pd(), cg);
  s.blockOf[k] = s.nBlocks;
  Block<3> &b = s.blocks[s.nBlocks++];
  // w[0..2][0..2] and g[0..2][0..2] are 18 consecutive doubles: four-wide stores in order, each
  // lane 3 overwritten by the next store, and the last one three wide
  static_assert(offsetof(Block<3>, g) == 9 * sizeof(double), "Block<3>: w, then g");
  for (int a = 0; a < 3; ++a)
    _mm256_storeu_pd(b.w[a], cw[a]);
  _mm256_storeu_pd(b.g[0], cg[0]);
  _mm256_storeu_pd(b.g[1], cg[1]);
  _mm_storeu_pd(b.g[2], _mm256_castpd256_pd128(cg[2]));
  _mm_store_sd(&b.g[2][2], _mm256_extractf128_pd(cg[2], 1));
  b.base = base;
  b.stride[0] = L.wn(0);
  b.stride[1] = L.wn(0) * L.wn(1);
  return true;
}
} // namespace
#endif

template <int D>
bool Grid<D>::blockRun(PetscInt k, const double *x, const double *l, Stencils<D> &s) const {
#if GIMP_HAVE_LANES
  if constexpr (D == 2)
    return blockRunLanes(*this, compactThree(), outwardReach_.data(), k, x, l, s);
#endif
  (void)k, (void)x, (void)l, (void)s;
  return false;
}

template <int D>
bool Grid<D>::blockLanes(int q, PetscInt k, const double *x, const double *l,
                         Stencils<D> &s) const {
#if GIMP_HAVE_LANES
  if constexpr (D == 3)
    return blockLanes3(*this, compactThree(), outwardReach_.data(), q, k, x, l, s);
#endif
  (void)q, (void)k, (void)x, (void)l, (void)s;
  return false;
}

template bool Grid<2>::blockRun(PetscInt, const double *, const double *, Stencils<2> &) const;
template bool Grid<3>::blockRun(PetscInt, const double *, const double *, Stencils<3> &) const;
template bool Grid<2>::blockLanes(int, PetscInt, const double *, const double *,
                                  Stencils<2> &) const;
template bool Grid<3>::blockLanes(int, PetscInt, const double *, const double *,
                                  Stencils<3> &) const;

} // namespace gimp
