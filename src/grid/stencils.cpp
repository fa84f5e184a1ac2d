// Stencils of particles on the composite grid: for each particle the active nodes whose support
// overlaps it, with the 1D GIMP weights and gradients of Eq. 15 along x and y.
#include "gimp/core/lanes.hpp"
#include "gimp/grid/grid.hpp"
#include "gimp/grid/shape.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace gimp {

namespace {

/// floor and ceil to an integer without a libm call (the hot loop of buildStencils).
inline PetscInt ifloor(double v) {
  const PetscInt i = static_cast<PetscInt>(v);
  return i - (v < static_cast<double>(i));
}
inline PetscInt iceil(double v) {
  const PetscInt i = static_cast<PetscInt>(v);
  return i + (v > static_cast<double>(i));
}

/// Readies s for the stencils of n particles: their starts, with `compact` their blocks, with
/// `lanes` their lane groups (none marked yet).
template <int D> void startStencils(PetscInt n, bool compact, bool lanes, Stencils<D> &s) {
  s.start.resize(static_cast<size_t>(n) + 1);
  s.general = false;
  s.compact = compact;
  if (compact) {
    s.blockOf.resize(static_cast<size_t>(n));
    s.reserveBlocks();
    s.nBlocks = 0;
    s.nBlocks4 = 0;
  }
  s.laneGroup.assign(lanes ? static_cast<size_t>(n / 4) : 0, 0);
  // Rows: room for the previous step's entries (or 10 per particle); grows below if needed.
  if (!compact) s.reserve(10 * static_cast<size_t>(n));
}

/// Particles k+1 .. n-1 keep no entries (the first m entries are all there are) and no blocks,
/// and s no lane groups: what buildStencils leaves when particle k is too large.
template <int D> void abandonStencils(PetscInt k, PetscInt n, size_t m, Stencils<D> &s) {
  for (PetscInt j = k + 1; j <= n; ++j)
    s.start[j] = static_cast<PetscInt>(m);
  if (s.compact)
    for (PetscInt j = k + 1; j < n; ++j)
      s.blockOf[j] = -1;
  s.laneGroup.clear();
}

} // namespace

template <int D> int Grid<D>::coarsestReaching(const double *x, const double *l) const {
  // A particle inside a finer box (closed) is out of reach of every coarser level: their active
  // nodes lie outside that box, on its lines, so their supports end on its boundary at the
  // latest.
  for (int q = static_cast<int>(levels.size()) - 1; q > 0; --q) {
    const BoxOf<D> &f = levels[q].box;
    bool inside = true;
    for (int a = 0; a < D; ++a)
      inside = inside && x[a] - l[a] >= f[a] && x[a] + l[a] <= f[D + a];
    if (inside) return q;
  }
  return 0;
}

template <int D>
GIMP_ALWAYS_INLINE bool Grid<D>::levelReach(int q, const double *x, const double *l,
                                            Reach &r) const {
  const Level<D> &L = levels[q];
  for (int a = 0; a < D; ++a)
    if (L.w1[a] <= L.w0[a]) return false;
  // Along an axis where the particle's centre lies within its box's range a level's nodes reach
  // it by at most h (the side of a node that faces it has zone h or less); along the others its
  // boundary nodes reach out by their outward zones (the coarser cell widths next to the box).
  r.inside = true;
  double lo[D], hi[D];
  for (int a = 0; a < D; ++a) {
    const bool within = x[a] >= L.box[a] && x[a] <= L.box[D + a];
    r.inside = r.inside && within;
    const double Zr = within ? L.h : outwardReach_[q];
    lo[a] = x[a] - l[a] - Zr;
    hi[a] = x[a] + l[a] + Zr;
  }
  const double ih = L.ih;
  bool first = true, small = true, four = D == 2;
  for (int a = 0; a < D; ++a) {
    const PetscInt ir = ifloor((lo[a] - L.box[a]) * ih) + 1;
    r.i0[a] = std::max(ir, L.w0[a]);
    r.i1[a] = std::min(iceil((hi[a] - L.box[a]) * ih) - 1, L.w1[a] - 1);
    if (r.i1[a] < r.i0[a]) return false;
    first = first && ir == r.i0[a];
    small = small && r.i1[a] - r.i0[a] <= 2 && r.i0[a] + 2 < L.w1[a] && l[a] <= 0.5 * L.h;
    four = four && r.i1[a] - r.i0[a] <= 3 && r.i0[a] + 3 < L.w1[a] && l[a] <= L.h;
  }
  r.threeNodeBlock = r.inside && first && small && threeNodeBlocks_[windowSlot(q, r.i0)];
  r.fourNodeBlock =
      !r.threeNodeBlock && r.inside && first && four && fourNodeBlocks_[windowSlot(q, r.i0)];
  return true;
}

template <int D>
GIMP_ALWAYS_INLINE int Grid<D>::soleBlock(int q, const double *x, const double *l,
                                          PetscInt *i0) const {
  // levelReach's conditions for a block, in its own arithmetic: the centre inside the box (so
  // the reach is h), l <= h / 2 (3 nodes) or, in 2D, l <= h on every axis and more than h / 2
  // on one (4 nodes), the candidates [ir, i1] within the window and at most that wide.
  const Level<D> &L = levels[q];
  int side = 3;
  for (int a = 0; a < D; ++a) {
    if (!(x[a] >= L.box[a] && x[a] <= L.box[D + a] && l[a] <= L.h)) return 0;
    if (!(l[a] <= 0.5 * L.h)) side = 4;
  }
  if (D == 3 && side == 4) return 0;
  for (int a = 0; a < D; ++a) {
    const PetscInt ir = ifloor((x[a] - l[a] - L.h - L.box[a]) * L.ih) + 1;
    const PetscInt i1 = iceil((x[a] + l[a] + L.h - L.box[a]) * L.ih) - 1;
    if (ir < L.w0[a] || ir + side - 1 >= L.w1[a] || i1 - ir > side - 1) return 0;
    i0[a] = ir;
  }
  if (!(side == 3 ? threeNodeBlocks_ : fourNodeBlocks_)[windowSlot(q, i0)]) return 0;
  // No finer level reaches it: along some axis its reach (with half a cell to spare) misses the
  // finer box, so levelReach finds no candidate there. Coarser levels never reach it.
  for (int f = q + 1; f < static_cast<int>(levels.size()); ++f) {
    const Level<D> &F = levels[f];
    const double Z = std::max(F.h, outwardReach_[f]) + 0.5 * F.h;
    bool misses = false;
    for (int a = 0; a < D; ++a)
      misses = misses || x[a] + l[a] + Z < F.box[a] || x[a] - l[a] - Z > F.box[D + a];
    if (!misses) return 0;
  }
  return side;
}

template <int D>
GIMP_ALWAYS_INLINE void Grid<D>::setBlock(int q, const PetscInt *i0, const double *x,
                                          const double *l, Stencils<D> &s, PetscInt k) const {
  // One level's regular 3^D block from node i0: the arguments appendThreeNodeBlock gives
  // shape::threeNodeWeights, so the factors are those the rows would hold.
  const Level<D> &L = levels[q];
  double xi[D], lam[D];
  PetscInt stride[D];
  for (int a = 0; a < D; ++a) {
    xi[a] = (x[a] - (L.box[a] + i0[a] * L.h)) * L.ih;
    lam[a] = l[a] * L.ih;
    stride[a] = a == 0 ? 1 : stride[a - 1] * L.wn(a - 1);
  }
  s.setBlock(k, windowSlot(q, i0), stride, xi, lam, L.ih);
}

template <int D>
GIMP_ALWAYS_INLINE void Grid<D>::setBlock4(int q, const PetscInt *i0, const double *x,
                                           const double *l, Stencils<D> &s, PetscInt k) const {
  // The 1D weights of the 4 nodes in closed form (shape::fourNodeWeights): the values
  // appendNodes gives a regular node with the particle inside its level's box, to round-off.
  if constexpr (D == 2) { // both axes at once, in closed form
    using simd::Pair;
    const Level<D> &L = levels[q];
    const Pair x2 = {x[0], x[1]}, l2 = {l[0], l[1]},
               corner = {L.box[0] + i0[0] * L.h, L.box[1] + i0[1] * L.h};
    const Pair xi = (x2 - corner) * L.ih, lam = l2 * L.ih, i2l = 0.5 / lam;
    Pair wp[4], gp[4];
    shape::fourNodeWeights(xi, lam, i2l, i2l * L.ih, wp, gp);
    double w[2][4], g[2][4];
    for (int i = 0; i < 4; ++i)
      for (int a = 0; a < 2; ++a) {
        w[a][i] = wp[i][a];
        g[a][i] = gp[i][a];
      }
    s.setBlock4(k, windowSlot(q, i0), L.wn(0), w, g);
  }
}

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

/// setBlock's factors of four particles in lanes: the weights w and derivatives g of their
/// 3-node blocks on level L from nodes fi.
GIMP_LANES_INLINE void laneFactors(const Level<2> &L, const V4 *X, const V4 *Lh, const V4 *fi,
                                   V4 w[2][3], V4 g[2][3]) {
  const V4 h = _mm256_set1_pd(L.h), ih = _mm256_set1_pd(L.ih);
  // setBlock: xi = (x - (box + i0 h)) / h, lam = l / h, then shape::threeNodeWeights per axis
  for (int a = 0; a < 2; ++a)
    laneThreeNodeWeights((X[a] - (_mm256_set1_pd(L.box[a]) + fi[a] * h)) * ih, Lh[a] * ih, ih, w[a],
                         g[a]);
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
  alignas(16) PetscInt base[4];
  laneSlots(grid, q, fi, base);
  if (!(threeNodeBlocks[base[0]] && threeNodeBlocks[base[1]] && threeNodeBlocks[base[2]] &&
        threeNodeBlocks[base[3]]))
    return false;
  V4 w[2][3], g[2][3];
  laneFactors(grid.levels[q], X, Lh, fi, w, g);
  storeLaneGroup(grid.levels[q], k, base, w, g, s);
  return true;
}

/// The three doubles at p in lanes 0-2, lane 3 zero.
GIMP_LANES_INLINE V4 laneLoad3(const double *p) {
  return _mm256_blend_pd(_mm256_zextpd128_pd256(_mm_loadu_pd(p)), _mm256_broadcast_sd(p + 2),
                         0b0100);
}

/// GridT<3>::blockLanes: soleBlock's tests and setBlock's factors with the three axes in lanes
/// 0-2, each lane the scalar arithmetic of its axis in its order (no FMA: this file has no
/// contraction). Lane 3 carries a half-size of one cell and is never used.
GIMP_LANES bool blockLanes3(const Grid<3> &grid, const std::uint8_t *threeNodeBlocks,
                            const double *outwardReach, int q, PetscInt k, const double *x,
                            const double *l, Stencils<3> &s) {
  const Level<3> &L = grid.levels[q];
  const V4 X = laneLoad3(x + 3 * k), Lh = laneLoad3(l + 3 * k);
  const V4 box0 = laneLoad3(&L.box[0]), box1 = laneLoad3(&L.box[3]);
  const V4 h = _mm256_set1_pd(L.h), ih = _mm256_set1_pd(L.ih);
  // soleBlock: the centre inside the box, l <= h / 2, candidates [ir, i1] in the window and at
  // most 3 wide
  V4 ok = _mm256_and_pd(_mm256_cmp_pd(X, box0, _CMP_GE_OQ), _mm256_cmp_pd(X, box1, _CMP_LE_OQ));
  ok = _mm256_and_pd(ok, _mm256_cmp_pd(Lh, _mm256_set1_pd(0.5 * L.h), _CMP_LE_OQ));
  const V4 ir = _mm256_floor_pd((X - Lh - h - box0) * ih) + 1.0;
  const V4 i1 = _mm256_ceil_pd((X + Lh + h - box0) * ih) - 1.0;
  const V4 w0 = _mm256_set_pd(0.0, L.w0[2], L.w0[1], L.w0[0]);
  const V4 w1 = _mm256_set_pd(0.0, L.w1[2], L.w1[1], L.w1[0]);
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
    const V4 misses = _mm256_or_pd(_mm256_cmp_pd(X + Lh + Z, laneLoad3(&F.box[0]), _CMP_LT_OQ),
                                   _mm256_cmp_pd(X - Lh - Z, laneLoad3(&F.box[3]), _CMP_GT_OQ));
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
    return blockRunLanes(*this, threeNodeBlocks_.data(), outwardReach_.data(), k, x, l, s);
#endif
  (void)k, (void)x, (void)l, (void)s;
  return false;
}

template <int D>
bool Grid<D>::blockLanes(int q, PetscInt k, const double *x, const double *l,
                         Stencils<D> &s) const {
#if GIMP_HAVE_LANES
  if constexpr (D == 3)
    return blockLanes3(*this, threeNodeBlocks_.data(), outwardReach_.data(), q, k, x, l, s);
#endif
  (void)q, (void)k, (void)x, (void)l, (void)s;
  return false;
}

template <int D>
bool Grid<D>::buildStencils(PetscInt n, const double *x, const double *l, Stencils<D> &s,
                            bool compact, bool lanes) const {
  const int K = static_cast<int>(levels.size());
  // Lane groups (2D): each aligned group of four tries blockRun, which marks the groups it builds;
  // in 3D each particle tries blockLanes first.
  const bool lanes3 = lanes && compact && D == 3;
  lanes = lanes && compact && D == 2;
  startStencils(n, compact, lanes, s);
  size_t m = 0;
  // A candidate range spans at most 2 (l + Z) / h + 1 nodes with l, Z <= h0 (l is checked
  // every step): size the scratch for the finest level.
  const PetscInt maxRange = static_cast<PetscInt>(4.0 * levels[0].h / levels.back().h) + 4;
  std::vector<double> scratch(6 * D * static_cast<size_t>(maxRange)); // (appendNodes' tables)
  std::vector<Reach> reach(K);
  std::vector<char> reaches(K);
  // Aligned groups of four blocks in lanes; a group that is not one goes one by one.
  for (PetscInt k = 0; k < n; ++k) {
    if constexpr (D == 2)
      if (lanes && k % 4 == 0 && k + 4 <= n && blockRun(k, x, l, s)) {
        for (int q = 0; q < 4; ++q)
          s.start[k + q] = static_cast<PetscInt>(m);
        k += 3;
        continue;
      }
    s.start[k] = static_cast<PetscInt>(m);
    const double *xp = x + D * k, *lp = l + D * k;
    const int first = coarsestReaching(xp, lp);
    if (compact) {
      if (lanes3 && blockLanes(first, k, x, l, s)) continue;
      s.blockOf[k] = -1;
      PetscInt i0[D];
      const int side = soleBlock(first, xp, lp, i0); // the common case, in a few comparisons
      if (side == 3) {
        setBlock(first, i0, xp, lp, s, k);
        continue;
      }
      if (side == 4) {
        setBlock4(first, i0, xp, lp, s, k);
        continue;
      }
    }
    int nReach = 0, last = -1;
    for (int q = 0; q < K; ++q) {
      reaches[q] = q >= first && levelReach(q, xp, lp, reach[q]);
      if (reaches[q]) ++nReach, last = q;
    }
    if (compact && nReach == 1 && reach[last].threeNodeBlock) {
      setBlock(last, reach[last].i0, xp, lp, s, k);
      continue;
    }
    if (compact && nReach == 1 && reach[last].fourNodeBlock) {
      setBlock4(last, reach[last].i0, xp, lp, s, k);
      continue;
    }
    for (int q = 0; q < K; ++q) {
      if (!reaches[q]) continue;
      const Reach &r = reach[q];
      if (r.threeNodeBlock) {
        appendThreeNodeBlock(q, r, xp, lp, s, m);
        continue;
      }
      bool tooLarge = false; // a particle larger than h0
      for (int a = 0; a < D; ++a)
        tooLarge = tooLarge || r.i1[a] - r.i0[a] >= maxRange;
      if (tooLarge) { // the rest keep no entries (the step fails at its check)
        abandonStencils(k, n, m, s);
        return false;
      }
      appendNodes(q, r, xp, lp, scratch.data(), maxRange, s, m);
    }
  }
  s.start[n] = static_cast<PetscInt>(m);
  return true;
}

template bool Grid<2>::levelReach(int, const double *, const double *, Reach &) const;
template bool Grid<3>::levelReach(int, const double *, const double *, Reach &) const;
template int Grid<2>::soleBlock(int, const double *, const double *, PetscInt *) const;
template int Grid<3>::soleBlock(int, const double *, const double *, PetscInt *) const;
template void Grid<2>::setBlock4(int, const PetscInt *, const double *, const double *,
                                 Stencils<2> &, PetscInt) const;
template void Grid<3>::setBlock4(int, const PetscInt *, const double *, const double *,
                                 Stencils<3> &, PetscInt) const;
template void Grid<2>::setBlock(int, const PetscInt *, const double *, const double *,
                                Stencils<2> &, PetscInt) const;
template void Grid<3>::setBlock(int, const PetscInt *, const double *, const double *,
                                Stencils<3> &, PetscInt) const;
template int Grid<2>::coarsestReaching(const double *, const double *) const;
template bool Grid<2>::blockRun(PetscInt, const double *, const double *, Stencils<2> &) const;
template bool Grid<3>::blockRun(PetscInt, const double *, const double *, Stencils<3> &) const;
template bool Grid<2>::blockLanes(int, PetscInt, const double *, const double *,
                                  Stencils<2> &) const;
template bool Grid<3>::blockLanes(int, PetscInt, const double *, const double *,
                                  Stencils<3> &) const;
template int Grid<3>::coarsestReaching(const double *, const double *) const;
template bool Grid<2>::buildStencils(PetscInt, const double *, const double *, Stencils<2> &, bool,
                                     bool) const;
template bool Grid<3>::buildStencils(PetscInt, const double *, const double *, Stencils<3> &, bool,
                                     bool) const;

} // namespace gimp
