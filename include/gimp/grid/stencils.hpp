// Particle -> node weights of GIMP (Eq. 15), for any dimension D, in two forms.
//
// Rows: entries start[k] .. start[k+1]-1 belong to particle k; each names a slot of the window's
// nodal arrays (a window node: one velocity field per node; see docs/architecture.md for how a
// second field at cracked nodes adds slots) and carries the 1D weights w[d] and their derivatives
// g[d] along every axis d. The weight is their product (Eq. 11) and the gradient's component a is
// g[a] times the other axes' w. CPDI weights (Grid::buildCpdiStencils) are not tensor products:
// with `general` set an entry holds its weight sw, its gradient sg[a] and the point shape function
// of the node at each of the particle's 2^D corners, cw[2^D e + c] (for the particle's edges).
//
// Blocks (with `compact` set): a particle that only one level's nodes reach, each with zone h on
// the sides of its tent the particle overlaps (so a node on a finer box's face or on the domain's
// edge serves the particles on its regular side), keeps no entries but its 1D factors (Block: 2 or
// 3 nodes per axis, their weights and derivatives from the closed form shape::threeNodeWeights, the
// first slot and the slot strides): 104 bytes in 2D (blocks, in particle order; blockOf[k] finds
// particle k's) instead of 36 per entry (4 to 9 entries), the same values the rows would hold. In
// 2D a particle of half-size up to h that reaches 4 nodes along an axis (l > h/2, or ends on nodes)
// keeps a 4-node block (Block<2, 4>, 136 bytes, shape::fourNodeWeights: the rows' values to
// round-off) instead of 6 to 16 entries. Kernels with a tensor-product form sum along one axis,
// then the other. With lanes (2D), aligned groups of four block particles keep their four blocks
// factor-major in the same room (LaneBlocks, laneGroup); block(k) reads either form.
//
// Level blocks (3D, compact): a particle that two levels reach, or whose level's nodes are not all
// regular, keeps one LevelBlock per level (1D factors and a node mask) when each level's entries
// are a tensor product; others keep rows.
//
// forEach(k, f) calls f(slot, weight, gradient) for every entry of particle k in any form; it
// is the way kernels read stencils. The arrays keep their capacity between steps: only the first
// start[n] entries are valid.
#pragma once

#include "gimp/core/petsc_compat.hpp"
#include "gimp/core/prefetch.hpp"
#include "gimp/core/tensor.hpp"
#include "gimp/grid/shape.hpp"

#include <petscsys.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <utility>
#include <vector>

namespace gimp {

/// The 1D factors of a block particle: the weights w[d][i] and derivatives g[d][i] of the N
/// nodes along axis d (the last ones are 0 where the particle does not reach them, and in a 2D
/// lane group's block the first one may be: grid/stencil_lanes.cpp, alignedStarts); node
/// (i, j, ...) is slot base + i + j stride[0] + k stride[1] .... Kernels with a tensor-product
/// form use it directly (sums along one axis, then the other). N = 3 for particles of half-size
/// up to h/2 (104 bytes in 2D); N = 4 (2D only) for half-sizes up to h that reach 4 nodes along
/// an axis (136 bytes, against 36 per row entry and 6 to 16 entries).
template <int D, int N = 3> struct Block {
  double w[D][N], g[D][N];
  PetscInt base;
  PetscInt stride[D - 1];
};

/// One level's share of a particle that keeps neither kind of block (two levels reach it, or its
/// level's nodes there are not all regular), when those entries are a tensor product: the 1D
/// factors of up to 4 nodes per axis exactly as the rows would hold them (w[d][i], g[d][i] of the
/// node at index i along d, 0 where none), and the nodes that are entries (bit i + 4 j + 16 q of
/// `mask` for node (i, j, q), slot base + i + j stride[0] + q stride[1]). 216 bytes in 3D against
/// 52 per row entry and 8 to 70 entries per level; forEach forms a block's products (Block), so
/// the rows' values to round-off.
template <int D> struct LevelBlock {
  double w[D][4], g[D][4];
  std::uint64_t mask;
  PetscInt base;
  PetscInt stride[D - 1];
  std::uint8_t n[D]; // nodes along each axis (1 to 4)
  std::uint8_t last; // 1 on the particle's last level block
};

/// What the stencil build reads of the grid about one level's box of candidate nodes, at most 4
/// along each axis (Grid::patternOf): which nodes are active, regular (zone h on every side) and
/// live cracked nodes (bit c0 + 4 c1 + 16 c2), and, when every active node at index c along axis a
/// has the same zones there (`tensor`), those (Z, as indices into the grid's zone values). The
/// particles of one box then need only their 1D factors along each axis (a node's coordinate
/// along an axis depends on its level and its index there alone).
template <int D> struct NodePattern {
  std::uint64_t key = ~std::uint64_t{0}; // level, first slot and extents (none yet: all ones)
  std::uint64_t active = 0, regular = 0, live = 0;
  std::uint8_t Z[D][4][2];
  bool tensor = false;
  bool recent = false; // (Grid::PatternCache: the way of its pair used last)
};

/// A lane group's four 3-node blocks (2D) as the lane kernels read them, in the room of the four
/// Block<2> they replace: factor c of particle q at f[c][q] (factor-major: one load gives a factor
/// of all four), the factors in the order w[0][0..2], w[1][0..2], g[0][0..2], g[1][0..2]; then the
/// four first slots and row strides.
struct LaneBlocks {
  double f[12][4];
  PetscInt base[4], stride[4];
};
static_assert(sizeof(LaneBlocks) == 4 * sizeof(Block<2>),
              "a lane group's blocks take the room of four blocks");

/// An allocator that leaves new elements uninitialised (resize() of a vector of doubles does not
/// write them): the stencil arrays grow with room to spare, and untouched room costs no resident
/// memory.
template <class T> struct UninitAllocator : std::allocator<T> {
  template <class U> struct rebind { using other = UninitAllocator<U>; };
  UninitAllocator() = default;
  template <class U> UninitAllocator(const UninitAllocator<U> &) noexcept {}
  template <class U> void construct(U *p) noexcept { ::new (static_cast<void *>(p)) U; }
  template <class U, class... A> void construct(U *p, A &&...a) {
    ::new (static_cast<void *>(p)) U(std::forward<A>(a)...);
  }
};
template <class T> using StencilArray = std::vector<T, UninitAllocator<T>>;

template <int D> struct Stencils {
  static_assert(D == 2 || D == 3, "stencils in 2D or 3D");
  StencilArray<PetscInt> start;
  StencilArray<PetscInt> node;
  std::array<StencilArray<double>, D> w, g;
  bool general = false;
  StencilArray<double> sw, cw;
  std::array<StencilArray<double>, D> sg;

  // Blocks (see above). levelIh[q] = 1 / h of level q, levelStride[D q + d] the slot distance
  // of one node along axis d on level q's window.
  bool compact = false;
  // Per particle: its block in `blocks` (>= 0; with kLaneBlock set in a lane group), -1 (rows), or
  // -2 - its block in `blocks4`.
  StencilArray<PetscInt> blockOf;
  PetscInt nBlocks = 0, nBlocks4 = 0;
  StencilArray<Block<D>> blocks;     // the 3-node blocks, in particle order
  StencilArray<Block<D, 4>> blocks4; // the 4-node blocks (2D), in particle order
  // Groups of four particles for the lane kernels (2D, GridT::buildStencils with lanes): for
  // particles 4g .. 4g+3, kLaneGroup when the four are 3-node blocks of one level, built in lanes
  // (their blocks in the room of blocks[blockOf[4g]] .. +3, factor-major: LaneBlocks), ored with
  // bit q-1 when particle q's first slot differs from particle q-1's; 0 otherwise. Empty without
  // lanes: then no group is one.
  static constexpr std::uint8_t kLaneGroup = 0x80;
  // blockOf of a lane group's particle: its slot in `blocks` with this bit set (block() reads the
  // factor-major room then; a rank holds far fewer than 2^30 particles).
  static constexpr PetscInt kLaneBlock = PetscInt(1) << (8 * sizeof(PetscInt) - 2);
  StencilArray<std::uint8_t> laneGroup;
  /// The lane group byte of group g (0 when the stencils were built without lanes).
  std::uint8_t laneGroupOf(PetscInt g) const {
    return static_cast<size_t>(g) < laneGroup.size() ? laneGroup[g] : 0;
  }

  // Level blocks (compact) where they take less room than the fewest rows a level gives (2^D
  // entries): in 3D (216 bytes against 8 x 52), not in 2D (152 against 4 x 36; measured on
  // bench/block3.opts they cost 6 % of the step and saved no memory).
  static constexpr bool kLevelBlocks = (size_t{1} << D) *
                                           (sizeof(PetscInt) + 2 * D * sizeof(double)) >
                                       sizeof(LevelBlock<D>);
  // levelOf[k] is particle k's first block in levelBlocks (its others follow, the last marked),
  // or -1; levelOf is empty while no particle has them (the first that does sizes it).
  StencilArray<PetscInt> levelOf;
  // With node patterns (Grid::buildStencils with patterns): the patterns this build looked up,
  // particle k's from patternStart[k] to patternStart[k + 1], and the last build's (the `Last`
  // pair), with the generation of the grid's pattern table they came from. The next build of
  // these particles finds a particle's boxes among its last patterns, in order, before it asks
  // the table (a pattern is its key's whichever particle met it).
  std::vector<NodePattern<D>> patterns, patternsLast;
  std::vector<PetscInt> patternStart, patternStartLast;
  std::uint64_t patternGeneration = ~std::uint64_t{0};
  // Where the built particles start in their swarm (set by the caller: a rate class's first
  // particle, MultiRate::startClass), and where they started at the last build with patterns: a
  // particle's patterns of the last build are found by its place in the swarm, which a class's
  // particles keep when the classes' ranges move.
  PetscInt swarmOrigin = 0, patternOrigin = 0;
  PetscInt nLevelBlocks = 0;
  StencilArray<LevelBlock<D>> levelBlocks;
  /// True when particle k keeps level blocks (it has no row entries then).
  bool isLevels(PetscInt k) const { return compact && !levelOf.empty() && levelOf[k] >= 0; }

  double weight(PetscInt e) const {
    if (general) return sw[e];
    double s = w[0][e];
    for (int d = 1; d < D; ++d)
      s *= w[d][e];
    return s;
  }
  Vector<D> gradient(PetscInt e) const {
    Vector<D> r;
    if (general) {
      for (int a = 0; a < D; ++a)
        r[a] = sg[a][e];
      return r;
    }
    for (int a = 0; a < D; ++a) {
      double s = g[a][e];
      for (int d = 0; d < D; ++d)
        if (d != a) s *= w[d][e];
      r[a] = s;
    }
    return r;
  }
  /// One row (along x) of a level block as the kernels walk it: the slot of its first node, the
  /// (y, z) factors of the weight (wyz) and of the gradient's y and z components (gy, gz; gz 0
  /// in 2D), the nodes along x that are entries (bit i), the x factors, and the row's block and
  /// indices j, q along y and z (for a pass that needs each factor: a face's force).
  struct LevelRow {
    PetscInt slot;
    double wyz, gy, gz;
    unsigned nodes;
    const double *w0, *g0;
    const LevelBlock<D> *block;
    int j, q;
  };
  /// The rows of level-block particle k one by one (rows without entries skipped), block by
  /// block; a plain loop the lane kernels can inline. A block's entry bits lie within its n
  /// nodes along each axis (setLevelBlock, appendThreeNodeBlock), so its rows with entries are
  /// the nonzero 4-bit groups of its mask, row j + 4 q at bits 4 (j + 4 q), in the order of q
  /// then j.
  struct LevelRows {
    const LevelBlock<D> *b;
    std::uint64_t rest; // the entry bits of b's rows not walked yet
    GIMP_ALWAYS_INLINE bool next(LevelRow &r) {
      while (!rest) {
        if (b->last) return false;
        rest = (++b)->mask;
      }
      const int t = __builtin_ctzll(rest) >> 2, j = t & 3, q = t >> 2; // (the row)
      r.nodes = static_cast<unsigned>(rest >> (4 * t)) & 15u;
      rest &= ~(std::uint64_t{15} << (4 * t));
      r.block = b, r.j = j, r.q = q;
      r.w0 = b->w[0];
      r.g0 = b->g[0];
      r.slot = b->base + j * b->stride[0];
      if constexpr (D == 3) {
        r.slot += q * b->stride[1];
        r.wyz = b->w[1][j] * b->w[2][q];
        r.gy = b->g[1][j] * b->w[2][q];
        r.gz = b->w[1][j] * b->g[2][q];
      } else {
        r.wyz = b->w[1][j];
        r.gy = b->g[1][j];
        r.gz = 0.0;
      }
      return true;
    }
  };
  LevelRows levelRows(PetscInt k) const {
    const LevelBlock<D> *b = levelBlocks.data() + levelOf[k];
    return {b, b->mask};
  }
  /// f(slot, weight, gradient) for node i of row r: the products of a block's (Block::forEach).
  template <class F> static GIMP_ALWAYS_INLINE void levelNode(const LevelRow &r, int i, F &f) {
    Vector<D> gr;
    gr[0] = r.g0[i] * r.wyz;
    gr[1] = r.w0[i] * r.gy;
    if constexpr (D == 3) gr[2] = r.w0[i] * r.gz;
    f(r.slot + i, r.w0[i] * r.wyz, gr);
  }
  /// forEach of level-block particle k, out of line (it keeps the kernels' block paths lean).
  template <class F> __attribute__((noinline)) void forEachLevelNode(PetscInt k, F &f) const {
    LevelRow r;
    for (LevelRows rows = levelRows(k); rows.next(r);)
      for (int i = 0; i < 4; ++i)
        if ((r.nodes >> i) & 1u) levelNode(r, i, f);
  }
  /// Room for `more` level blocks after the first nLevelBlocks (growing by half at least).
  /// Room for `want` level blocks, reserved before the first is written: untouched room costs
  /// no resident memory (UninitAllocator), whereas growing the array while it fills would hold
  /// the old and the new copy at once (the first step's peak).
  void roomForLevelBlocks(size_t want) {
    if (levelBlocks.size() >= want) return;
    StencilArray<LevelBlock<D>>().swap(levelBlocks); // (nothing in it to keep)
    levelBlocks.resize(want);
  }
  void reserveLevelBlocks(size_t more) {
    const size_t want = static_cast<size_t>(nLevelBlocks) + more;
    if (levelBlocks.size() < want)
      levelBlocks.resize(std::max(want, levelBlocks.size() + levelBlocks.size() / 2));
  }
  /// True when particle k keeps a 3-node block instead of rows.
  bool isBlock(PetscInt k) const { return compact && blockOf[k] >= 0; }
  /// True when particle k keeps a 4-node block (2D).
  bool isBlock4(PetscInt k) const { return compact && blockOf[k] <= -2; }
  /// The 1D factors of block particle k (isBlock(k)), also of a lane group's (a copy).
  Block<D> block(PetscInt k) const {
    const PetscInt o = blockOf[k];
    if constexpr (D == 2)
      if (o & kLaneBlock) return laneBlock(k);
    return blocks[o];
  }
  /// The room of lane group g's blocks (laneGroupOf(g) != 0), read as LaneBlocks.
  const unsigned char *laneBlocks(PetscInt g) const {
    return reinterpret_cast<const unsigned char *>(blocks.data() + (blockOf[4 * g] & ~kLaneBlock));
  }
  unsigned char *laneBlocks(PetscInt g) {
    return reinterpret_cast<unsigned char *>(blocks.data() + (blockOf[4 * g] & ~kLaneBlock));
  }
  /// Asks for the cache lines of lane group g's room (2D), if g is a lane group.
  void prefetchGroup(PetscInt g) const {
    if constexpr (D == 2)
      if (laneGroupOf(g)) prefetch::span<sizeof(LaneBlocks)>(laneBlocks(g));
  }
  /// Particle k's block out of its lane group's factor-major room (2D).
  Block<2> laneBlock(PetscInt k) const {
    const unsigned char *r = laneBlocks(k / 4);
    const size_t q = static_cast<size_t>(k % 4), d = sizeof(double), i = sizeof(PetscInt);
    const auto factor = [&](size_t c) { return r + offsetof(LaneBlocks, f) + (4 * c + q) * d; };
    Block<2> b;
    for (size_t c = 0; c < 3; ++c) {
      std::memcpy(&b.w[0][c], factor(c), d);
      std::memcpy(&b.w[1][c], factor(3 + c), d);
      std::memcpy(&b.g[0][c], factor(6 + c), d);
      std::memcpy(&b.g[1][c], factor(9 + c), d);
    }
    std::memcpy(&b.base, r + offsetof(LaneBlocks, base) + q * i, i);
    std::memcpy(&b.stride[0], r + offsetof(LaneBlocks, stride) + q * i, i);
    return b;
  }
  /// The 1D factors of 4-node block particle k (isBlock4(k)).
  const Block<D, 4> &block4(PetscInt k) const { return blocks4[-2 - blockOf[k]]; }
  /// Room for a block per particle (untouched room costs no memory); before setBlock.
  void reserveBlocks() {
    if (blocks.size() < blockOf.size()) blocks.resize(blockOf.size());
    if (D == 2 && blocks4.size() < blockOf.size()) blocks4.resize(blockOf.size());
  }
  /// Make particle k a 4-node block (2D): base slot, row stride, and the 1D weights and
  /// derivatives of its 4 nodes along x and along y.
  void setBlock4(PetscInt k, PetscInt base, PetscInt stride, const double (*w)[4],
                 const double (*g)[4]) {
    blockOf[k] = -2 - nBlocks4;
    Block<D, 4> &b = blocks4[nBlocks4++];
    for (int d = 0; d < D; ++d)
      for (int i = 0; i < 4; ++i) {
        b.w[d][i] = w[d][i];
        b.g[d][i] = g[d][i];
      }
    b.base = base;
    b.stride[0] = stride;
  }
  /// Make particle k a block: base slot, strides, and per axis the particle's left end in the
  /// block's first cell xi[d], its half-size in cells lam[d] and 1 / h of its level.
  void setBlock(PetscInt k, PetscInt base, const PetscInt *stride, const double *xi,
                const double *lam, double ih) {
    blockOf[k] = nBlocks;
    Block<D> &b = blocks[nBlocks++];
    { // x and y at once (one SSE2 pair), then z
      using simd::Pair;
      const Pair x2 = {xi[0], xi[1]}, l2 = {lam[0], lam[1]}, i2l = 0.5 / l2;
      Pair w[3], g[3];
      shape::threeNodeWeights(x2, l2, i2l, i2l * ih, w, g);
      for (int i = 0; i < 3; ++i)
        for (int d = 0; d < 2; ++d) {
          b.w[d][i] = w[i][d];
          b.g[d][i] = g[i][d];
        }
    }
    if constexpr (D == 3) {
      const double i2lz = 0.5 / lam[2];
      shape::threeNodeWeights(xi[2], lam[2], i2lz, i2lz * ih, b.w[2], b.g[2]);
    }
    for (int d = 1; d < D; ++d)
      b.stride[d - 1] = stride[d];
    b.base = base;
  }
  /// The nodes along axis d of a 4-node block up to the last one the particle reaches (with a
  /// weight or a slope): 2 to 4.
  static int nodesReached(const Block<2, 4> &b, int d) {
    int n = 4;
    while (n > 2 && b.w[d][n - 1] == 0.0 && b.g[d][n - 1] == 0.0)
      --n;
    return n;
  }
  /// f(slot, weight, gradient) for the nodes n0[d] .. nn[d] - 1 along each axis of a 2D block.
  template <int N, class F>
  static void forEachNode(const Block<2, N> &b, const int *n0, const int *nn, F &f) {
    for (int j = n0[1]; j < nn[1]; ++j)
      for (int i = n0[0]; i < nn[0]; ++i) {
        Vector<2> gr;
        gr[0] = b.g[0][i] * b.w[1][j];
        gr[1] = b.g[1][j] * b.w[0][i];
        f(b.base + j * b.stride[0] + i, b.w[0][i] * b.w[1][j], gr);
      }
  }
  /// f(slot, weight, gradient) for the row entries of particle k: weight(e) and gradient(e), the
  /// same products, with the arrays and `general` read once (f's stores to doubles could alias
  /// them, and each entry would load them again).
  template <class F> GIMP_ALWAYS_INLINE void forEachEntry(PetscInt k, F &f) const {
    const PetscInt e0 = start[k], e1 = start[k + 1];
    const PetscInt *nd = node.data();
    const double *wp[D], *gp[D];
    if (general) {
      const double *s = sw.data();
      for (int a = 0; a < D; ++a)
        gp[a] = sg[a].data();
      for (PetscInt e = e0; e < e1; ++e) {
        Vector<D> r;
        for (int a = 0; a < D; ++a)
          r[a] = gp[a][e];
        f(nd[e], s[e], r);
      }
      return;
    }
    for (int d = 0; d < D; ++d) {
      wp[d] = w[d].data();
      gp[d] = g[d].data();
    }
    for (PetscInt e = e0; e < e1; ++e) {
      double s = wp[0][e];
      for (int d = 1; d < D; ++d)
        s *= wp[d][e];
      Vector<D> r;
      for (int a = 0; a < D; ++a) {
        double t = gp[a][e];
        for (int d = 0; d < D; ++d)
          if (d != a) t *= wp[d][e];
        r[a] = t;
      }
      f(nd[e], s, r);
    }
  }
  /// f(slot, weight, gradient) for every entry of particle k.
  template <class F> void forEach(PetscInt k, F &&f) const {
    if constexpr (D == 2)
      if (isBlock4(k)) {
        const Block<2, 4> b = block4(k); // a copy: f's stores cannot alias it
        const int n0[2] = {0, 0}, nn[2] = {nodesReached(b, 0), nodesReached(b, 1)};
        return forEachNode(b, n0, nn, f);
      }
    if (!isBlock(k)) {
      if (isLevels(k)) return forEachLevelNode(k, f);
      return forEachEntry(k, f);
    }
    const Block<D> b = block(k); // a copy: f's stores cannot alias it
    // The third node is reached only when its weight is not 0, the first always but in a block
    // a lane group took one node early (its factors there 0: grid/stencil_lanes.cpp,
    // alignedStarts), so the entries are those of the particle's own block.
    int n0[D], nn[D];
    for (int d = 0; d < D; ++d) {
      n0[d] = b.w[d][0] == 0.0 && b.g[d][0] == 0.0 ? 1 : 0;
      nn[d] = b.g[d][2] > 0.0 ? 3 : 2;
    }
    if constexpr (D == 2) {
      forEachNode(b, n0, nn, f);
    } else {
      // (3D) Along x innermost, the (y, z) factors of the weight and gradient formed once per row.
      for (int q = n0[2]; q < nn[2]; ++q)
        for (int j = n0[1]; j < nn[1]; ++j) {
          const double wyz = b.w[1][j] * b.w[2][q], gy = b.g[1][j] * b.w[2][q],
                       gz = b.w[1][j] * b.g[2][q];
          const PetscInt row = b.base + j * b.stride[0] + q * b.stride[1];
          for (int i = n0[0]; i < nn[0]; ++i) {
            Vector<D> gr;
            gr[0] = b.g[0][i] * wyz;
            gr[1] = b.w[0][i] * gy;
            gr[2] = b.w[0][i] * gz;
            f(row + i, b.w[0][i] * wyz, gr);
          }
        }
    }
  }
  /// Give the memory back (before a frame is written: the next step rebuilds everything).
  void release() {
    Stencils<D> empty;
    std::swap(*this, empty);
  }
  /// Make room for at least `want` entries, growing by half at least.
  void reserve(size_t want) {
    if (node.size() >= want) return;
    const size_t cap = std::max(want, node.size() + node.size() / 2);
    node.resize(cap);
    for (int d = 0; d < D; ++d) {
      w[d].resize(cap);
      g[d].resize(cap);
    }
  }
  /// The same for general entries (weights, gradients and corner values).
  void reserveGeneral(size_t want) {
    if (sw.size() >= want) return;
    const size_t cap = std::max(want, sw.size() + sw.size() / 2);
    node.resize(std::max(node.size(), cap));
    sw.resize(cap);
    cw.resize((size_t{1} << D) * cap);
    for (int d = 0; d < D; ++d)
      sg[d].resize(cap);
  }
};

} // namespace gimp
