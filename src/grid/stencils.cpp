// Stencils of particles on the composite grid: for each particle the active nodes whose support
// overlaps it, with the 1D GIMP weights and gradients of Eq. 15 along x and y.
#include "gimp/core/pair.hpp"
#include "gimp/grid/grid.hpp"
#include "gimp/grid/rounding.hpp"
#include "gimp/grid/shape.hpp"

#include <algorithm>
#include <cstddef>
#include <vector>

namespace gimp {

namespace {

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
  s.nLevelBlocks = 0;
  s.levelOf.clear();
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
  bool first = true, small = true, four = D == 2;
  for (int a = 0; a < D; ++a) {
    PetscInt ir, last;
    candidates(L, a, lo[a], hi[a], ir, last);
    r.i0[a] = std::max(ir, L.w0[a]);
    r.i1[a] = std::min(last, L.w1[a] - 1);
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
    PetscInt ir, i1;
    candidates(L, a, x[a] - l[a] - L.h, x[a] + l[a] + L.h, ir, i1);
    if (ir < L.w0[a] || ir + side - 1 >= L.w1[a] || i1 - ir > side - 1) return 0;
    i0[a] = ir;
  }
  if (!(side == 3 ? compactThree() : compactFour())[windowSlot(q, i0)]) return 0;
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

template <int D>
bool Grid<D>::buildStencils(PetscInt n, const double *x, const double *l, Stencils<D> &s,
                            bool compact, bool lanes, bool patterns, BuildSeen *seen) const {
  return seen ? buildStencilsNoting<true>(n, x, l, s, compact, lanes, patterns, seen)
              : buildStencilsNoting<false>(n, x, l, s, compact, lanes, patterns, nullptr);
}

template <int D>
template <bool Notes>
bool Grid<D>::buildStencilsNoting(PetscInt n, const double *x, const double *l, Stencils<D> &s,
                                  bool compact, bool lanes, bool patterns, BuildSeen *seen) const {
  const int K = static_cast<int>(levels.size());
  // Lane groups (2D): each aligned group of four tries blockRun, which marks the groups it builds;
  // in 3D each particle tries blockLanes first (both in stencil_lanes.cpp).
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
  // The node patterns pay where a build meets each box many times: a rate class's particles at
  // every sub-step (3D; docs/performance.md, *Node patterns*). The single step does without: its
  // kept patterns cost 122 B per particle on bench/block3d_levels.opts for no speed that showed
  // above the machine's noise, and a 2D box has at most 16 nodes: reading them is as fast.
  PatternCache *cache = patterns && D == 3 ? &patterns_ : nullptr;
  // The last build's patterns (of this table's generation): particle k's are those of its place
  // in the swarm then, k + shift (Stencils::swarmOrigin).
  PetscInt nLast = 0, shift = 0;
  if (cache) {
    cache->ready();
    s.patterns.swap(s.patternsLast);
    s.patternStart.swap(s.patternStartLast);
    if (s.patternGeneration == cache->generation && !s.patternStartLast.empty())
      nLast = static_cast<PetscInt>(s.patternStartLast.size()) - 1;
    shift = s.swarmOrigin - s.patternOrigin;
    s.patternGeneration = cache->generation;
    s.patternOrigin = s.swarmOrigin;
    s.patterns.clear();
    s.patternStart.resize(static_cast<size_t>(n) + 1);
    cache->out = &s.patterns;
  }
  struct EndWalk { // (the walk's vectors are this build's: the cache forgets them at its end)
    PatternCache *c;
    ~EndWalk() {
      if (c) c->last = c->lastEnd = nullptr, c->out = nullptr;
    }
  } endWalk{cache};
  const bool tryLevels = compact && Stencils<D>::kLevelBlocks;
  if (tryLevels) s.roomForLevelBlocks(static_cast<size_t>(K) * static_cast<size_t>(n));
  const auto tooLarge = [&](const Reach &r) { // a particle larger than h0
    for (int a = 0; a < D; ++a)
      if (r.i1[a] - r.i0[a] >= maxRange) return true;
    return false;
  };
  // What `seen` notes (BuildSeen), each particle as it is read (in order), kept in locals (the
  // stencils' stores would otherwise reload them) and stored at the end; in 2D both axes at once
  // (simd::minOf, maxOf, bothLe lane by lane).
  BuildSeen none;
  BuildSeen &notes = seen ? *seen : none;
  notes.start();
  const bool watch = seen && seen->watch;
  const double widen = notes.reach;
  [[maybe_unused]] simd::Pair lo2{}, hi2{}, nearLo{}, nearHi{}, widen2{};
  [[maybe_unused]] double lo[D], hi[D];
  if constexpr (D == 2) {
    lo2 = simd::splat(notes.lo[0]);
    hi2 = simd::splat(notes.hi[0]);
    nearLo = simd::Pair{notes.near[0], notes.near[1]};
    nearHi = simd::Pair{notes.near[2], notes.near[3]};
    widen2 = simd::splat(widen);
  } else {
    for (int a = 0; a < D; ++a)
      lo[a] = notes.lo[a], hi[a] = notes.hi[a];
  }
  const BoxOf<D> near = notes.near;
  const auto note = [&](PetscInt k) {
    bool close = watch;
    if constexpr (D == 2) {
      const simd::Pair xk = simd::load(x + 2 * k), lk = simd::load(l + 2 * k);
      const simd::Pair xl = xk - lk, xh = xk + lk;
      lo2 = simd::minOf(xl, lo2);
      hi2 = simd::maxOf(xh, hi2);
      close = close && simd::bothLe(nearLo, xh + widen2) && simd::bothLe(xl - widen2, nearHi);
    } else {
      for (int a = 0; a < D; ++a) {
        const double xl = x[D * k + a] - l[D * k + a], xh = x[D * k + a] + l[D * k + a];
        lo[a] = std::min(lo[a], xl);
        hi[a] = std::max(hi[a], xh);
        close = close && near[a] <= xh + widen && xl - widen <= near[D + a];
      }
    }
    if (close) notes.nearParticles.push_back(k);
  };
  // Aligned groups of four blocks in lanes; a group that is not one goes one by one.
  for (PetscInt k = 0; k < n; ++k) {
    if constexpr (D == 2)
      if (lanes && k % 4 == 0 && k + 4 <= n && blockRun(k, x, l, s)) {
        for (int q = 0; q < 4; ++q) {
          s.start[k + q] = static_cast<PetscInt>(m);
          if constexpr (Notes) note(k + q);
        }
        k += 3;
        continue;
      }
    if constexpr (Notes) note(k);
    s.start[k] = static_cast<PetscInt>(m);
    if (cache) {
      s.patternStart[k] = static_cast<PetscInt>(s.patterns.size());
      const PetscInt was = k + shift;
      const bool had = was >= 0 && was < nLast;
      cache->last = had ? s.patternsLast.data() + s.patternStartLast[was] : nullptr;
      cache->lastEnd = had ? s.patternsLast.data() + s.patternStartLast[was + 1] : nullptr;
    }
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
    // (a block that holds a cracked node keeps rows: the flags of the compact path)
    bool crackFree = compact && nReach == 1;
    if (crackFree) {
      const Reach &r = reach[last];
      crackFree = (r.threeNodeBlock && compactThree()[windowSlot(last, r.i0)]) ||
                  (r.fourNodeBlock && compactFour()[windowSlot(last, r.i0)]);
    }
    if (crackFree && reach[last].threeNodeBlock) {
      setBlock(last, reach[last].i0, xp, lp, s, k);
      continue;
    }
    if (crackFree && reach[last].fourNodeBlock) {
      setBlock4(last, reach[last].i0, xp, lp, s, k);
      continue;
    }
    // Level blocks (compact): each level's entries as a LevelBlock when every level's are one;
    // otherwise rows.
    if (tryLevels) {
      s.reserveLevelBlocks(static_cast<size_t>(K));
      LevelBlock<D> *out = s.levelBlocks.data() + s.nLevelBlocks;
      int made = 0;
      bool blocks = true;
      for (int q = 0; q < K && blocks; ++q) {
        if (!reaches[q]) continue;
        const Reach &r = reach[q];
        const int got = tooLarge(r)        ? -1 // (the rows' path below says so)
                        : r.threeNodeBlock ? appendThreeNodeBlock(q, r, xp, lp, s, m, out + made)
                                           : appendNodes(q, r, xp, lp, scratch.data(), maxRange, s,
                                                         m, out + made, cache);
        blocks = got >= 0;
        made += got > 0;
      }
      if (blocks && made > 0) {
        out[made - 1].last = 1;
        if (s.levelOf.empty()) s.levelOf.assign(static_cast<size_t>(n), -1);
        s.levelOf[k] = s.nLevelBlocks;
        s.nLevelBlocks += made;
        continue;
      }
    }
    for (int q = 0; q < K; ++q) {
      if (!reaches[q]) continue;
      const Reach &r = reach[q];
      if (r.threeNodeBlock) {
        appendThreeNodeBlock(q, r, xp, lp, s, m);
        continue;
      }
      if (tooLarge(r)) { // the rest keep no entries (the step fails at its check)
        abandonStencils(k, n, m, s);
        return false;
      }
      appendNodes(q, r, xp, lp, scratch.data(), maxRange, s, m, nullptr, cache);
    }
  }
  s.start[n] = static_cast<PetscInt>(m);
  if (cache) s.patternStart[n] = static_cast<PetscInt>(s.patterns.size());
  for (int a = 0; a < D; ++a) {
    if constexpr (D == 2)
      notes.lo[a] = lo2[a], notes.hi[a] = hi2[a];
    else
      notes.lo[a] = lo[a], notes.hi[a] = hi[a];
  }
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
template int Grid<3>::coarsestReaching(const double *, const double *) const;
template bool Grid<2>::buildStencils(PetscInt, const double *, const double *, Stencils<2> &, bool,
                                     bool, bool, BuildSeen *) const;
template bool Grid<3>::buildStencils(PetscInt, const double *, const double *, Stencils<3> &, bool,
                                     bool, bool, BuildSeen *) const;

} // namespace gimp
