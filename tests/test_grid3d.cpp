// Unit tests of the composite grid in 3D: the lattice (include/gimp/grid/lattice.hpp, D = 3) with
// nested uniform levels of integer ratios, active nodes and influence zones [Lx-, Lx+, Ly-, Ly+,
// Lz-, Lz+], the GIMP weights built from them as products of the 1D weights of Eq. 15, and the
// grid (include/gimp/grid/grid.hpp, GridT<3>): its stencils, windows and scatter.
//
//   1. A hand-checked grid: named nodes' activity and zones (a face, an edge and a corner of a
//      fine box, nodes on the domain's faces).
//   2. Every location carries exactly one active node, whose zones are the widths of the leaf
//      cells next to it (per axis and side, the smallest of the four cells there).
//   3. Partition of unity, linear reproduction and their derivatives at 1e5 random particles
//      over 3-level layouts (5e4 over 2-level ones) with ratios 2, 3 and 4 (boxes in the middle,
//      on a parent's face and corner, along a domain edge, a one-cell slab, coinciding boxes),
//      for the lattice's weights and for the grid's stencils (rows and blocks), which must hold
//      the lattice's weights node by node.
//   3a. With a planar crack (and a region of its plane where it may grow): the blocks of the
//      compact path (built in lanes) equal the rows with every crossing segment's entry
//      re-addressed to the second field, with the nodes marked for the particles' largest
//      half-size (Grid::markLiveCracks, Grid::liveReachFor).
//   4. Any number of ranks (ctest: two, split as PETSc chooses and along z) gives the one-rank
//      P2G / G2P round trip.
//   5. Badly nested 3D layouts are rejected naming the option and the reason.
//
// All random sampling uses a fixed-seed std::mt19937_64, so every run checks the same points.
#include "gimp/grid/crack_fields.hpp"
#include "gimp/grid/grid.hpp"
#include "gimp/grid/lattice.hpp"
#include "gimp/grid/shape.hpp"

#include "grid_layouts3d.hpp"
#include "test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using gimp::test::at;
using gimp::test::Worst;

using gimp::test3d::boxesOf;
using gimp::test3d::D;
using gimp::test3d::drawParticle;
using gimp::test3d::kH0;
using gimp::test3d::Lattice3;
using gimp::test3d::latticeOf;
using gimp::test3d::Layout;
using gimp::test3d::Level3;
using gimp::test3d::threeLevelLayouts;
using gimp::test3d::twoLevelLayouts;
using Index = gimp::LatticeIndex<D>;
using Grid3 = gimp::Grid<D>;
using Stencils3 = gimp::Stencils<D>;

/// The lattice's nodes as tables per level: activity, coordinates and zones (what the grid's
/// window holds), so the weight sums below look nodes up instead of recomputing them.
struct Nodes {
  struct PerLevel {
    std::vector<char> active;
    std::vector<double> zone; // 6 per node
  };
  std::vector<PerLevel> lev;
  explicit Nodes(const Lattice3 &g) {
    lev.resize(g.levels.size());
    for (int k = 0; k < static_cast<int>(g.levels.size()); ++k) {
      const Level3 &L = g.levels[k];
      const size_t n = static_cast<size_t>(L.n[0]) * L.n[1] * L.n[2];
      lev[k].active.assign(n, 0);
      lev[k].zone.assign(6 * n, 0.0);
      gimp::forEachIndex<D>(L.n, [&](const Index &i) {
        const size_t id = index(L, i);
        lev[k].active[id] = g.nodeActive(k, i);
        if (lev[k].active[id]) g.zonesOf(k, i, &lev[k].zone[6 * id]);
      });
    }
  }
  static size_t index(const Level3 &L, const Index &i) {
    return static_cast<size_t>((i[2] * L.n[1] + i[1]) * L.n[0] + i[0]);
  }
};

/// Sums of one particle's weights and gradients over the active nodes of all levels.
struct Sums {
  double w = 0, lo = 0, hi = 0;
  double wr[3] = {0, 0, 0}; // sum w_i (x_i - x_p)
  double g[3] = {0, 0, 0};  // sum grad w_i
  double gr[3][3] = {{0}};  // sum grad_a w_i (x_i - x_p)_b
  long nodes = 0;
};

/// Each node's weight and gradient, by window slot (of a one-rank grid on the same layout).
using Entries = std::map<PetscInt, std::array<double, 4>>;

Sums weightSums(const Lattice3 &g, const Nodes &tab, const double *x, const double *l,
                const Grid3 *grid = nullptr, Entries *entries = nullptr) {
  Sums s;
  const double h0 = g.h0();
  for (int k = 0; k < static_cast<int>(g.levels.size()); ++k) {
    const Level3 &L = g.levels[k];
    // A node's zones are at most h0 (a fine box on its ancestors' faces borders level 0).
    const double reach = h0;
    std::array<PetscInt, 3> i0, i1;
    bool empty = false;
    for (int a = 0; a < D; ++a) {
      i0[a] = std::max<PetscInt>(
          0, static_cast<PetscInt>(std::floor((x[a] - l[a] - reach - L.box[a]) * L.ih)));
      i1[a] = std::min<PetscInt>(
          L.n[a] - 1, static_cast<PetscInt>(std::ceil((x[a] + l[a] + reach - L.box[a]) * L.ih)));
      empty = empty || i1[a] < i0[a];
    }
    if (empty) continue;
    Index i;
    for (i[2] = i0[2]; i[2] <= i1[2]; ++i[2])
      for (i[1] = i0[1]; i[1] <= i1[1]; ++i[1])
        for (i[0] = i0[0]; i[0] <= i1[0]; ++i[0]) {
          const size_t id = Nodes::index(L, i);
          if (!tab.lev[k].active[id]) continue;
          const double *z = &tab.lev[k].zone[6 * id];
          double w[3], dw[3], r[3];
          bool in = true;
          for (int a = 0; a < D; ++a) {
            r[a] = g.nodeCoordinate(k, a, i[a]) - x[a];
            in = in && gimp::shape::overlaps(-r[a], l[a], z[2 * a], z[2 * a + 1]);
            gimp::shape::weightAndGradient(-r[a], l[a], z[2 * a], z[2 * a + 1], w[a], dw[a]);
          }
          if (!in) continue;
          const double W = w[0] * w[1] * w[2];
          const double G[3] = {dw[0] * w[1] * w[2], w[0] * dw[1] * w[2], w[0] * w[1] * dw[2]};
          if (W == 0.0 && G[0] == 0.0 && G[1] == 0.0 && G[2] == 0.0) continue; // (touching)
          if (entries) {
            const PetscInt ii[3] = {static_cast<PetscInt>(i[0]), static_cast<PetscInt>(i[1]),
                                    static_cast<PetscInt>(i[2])};
            (*entries)[grid->windowSlot(k, ii)] = {W, G[0], G[1], G[2]};
          }
          ++s.nodes;
          s.w += W;
          s.lo = std::min(s.lo, W);
          s.hi = std::max(s.hi, W);
          for (int a = 0; a < D; ++a) {
            s.wr[a] += W * r[a];
            s.g[a] += G[a];
            for (int b = 0; b < D; ++b)
              s.gr[a][b] += G[a] * r[b];
          }
        }
  }
  return s;
}

// ---------------------------------------------------------------------------------------------
// 1. A hand-checked grid: domain 4 x 4 x 4 cells of h = 2 from the origin, fine box
//    [2, 6]^3 with ratio 2 (h = 1).

TEST(Grid3D, NamedNodes) {
  std::vector<gimp::LevelBox<D>> b = {{{0, 0, 0, 8, 8, 8}, 1}, {{2, 2, 2, 6, 6, 6}, 2}};
  Lattice3 g;
  g.setLevels(2.0, b);
  ASSERT_EQ(g.levels.size(), 2u);
  EXPECT_EQ(g.levels[1].n, (std::array<PetscInt, 3>{5, 5, 5}));
  EXPECT_EQ(g.unit, 1.0);
  auto zones = [&](int k, Index i) {
    std::array<double, 6> z;
    g.zonesOf(k, i, z.data());
    return z;
  };
  // A fine node in the box's interior: zones 1 everywhere.
  EXPECT_TRUE(g.nodeActive(1, {2, 2, 2}));
  EXPECT_EQ(zones(1, {2, 2, 2}), (std::array<double, 6>{1, 1, 1, 1, 1, 1}));
  // The coarse node at (4, 4, 4) lies in the fine box: inactive. So do those on its faces.
  EXPECT_FALSE(g.nodeActive(0, {2, 2, 2}));
  EXPECT_FALSE(g.nodeActive(0, {1, 2, 2}));
  EXPECT_FALSE(g.nodeActive(0, {1, 1, 1}));
  // A fine node on the box's x- face, (2, 4, 4): outward zone 2 (coarse cells), else 1.
  EXPECT_EQ(zones(1, {0, 2, 2}), (std::array<double, 6>{2, 1, 1, 1, 1, 1}));
  // A fine node on the x- face between coarse lines, (2, 3, 5): the same.
  EXPECT_EQ(zones(1, {0, 1, 3}), (std::array<double, 6>{2, 1, 1, 1, 1, 1}));
  // On the edge x- y- (2, 2, 4): outward 2 on x- and y-; the cells beyond the edge are coarse on
  // both sides, but the inner quarter of each side is fine, so the other zones are 1.
  EXPECT_EQ(zones(1, {0, 0, 2}), (std::array<double, 6>{2, 1, 2, 1, 1, 1}));
  // The box's corner (2, 2, 2): outward 2 on the three low sides.
  EXPECT_EQ(zones(1, {0, 0, 0}), (std::array<double, 6>{2, 1, 2, 1, 2, 1}));
  // The coarse node (0, 4, 4) on the domain's x- face: zone 0 outside, 2 elsewhere.
  EXPECT_TRUE(g.nodeActive(0, {0, 2, 2}));
  EXPECT_EQ(zones(0, {0, 2, 2}), (std::array<double, 6>{0, 2, 2, 2, 2, 2}));
  // The coarse node (2, 4, 0) on the domain's z- face, below the box: zone 0 below, and 2 on
  // every other side (the cells it touches are coarse).
  EXPECT_EQ(zones(0, {1, 2, 0}), (std::array<double, 6>{2, 2, 2, 2, 0, 2}));
  // Active node counts: 5^3 fine; 5^3 coarse minus the 3^3 inside the closed box.
  EXPECT_EQ(g.activeNodes(1), 125);
  EXPECT_EQ(g.activeNodes(0), 125 - 27);
  // The CSV header names the three axes and six zones.
  const std::string csv = g.activeNodesCsv();
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "level,x,y,z,Lxm,Lxp,Lym,Lyp,Lzm,Lzp");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 125 + 98);
}

// ---------------------------------------------------------------------------------------------
// 2. One active node per location, with zones of leaf-cell widths.

TEST(Grid3D, OneActiveNodePerLocation) {
  std::vector<Layout> all = twoLevelLayouts();
  for (const Layout &l : threeLevelLayouts())
    all.push_back(l);
  for (const Layout &lay : all) {
    const Lattice3 g = latticeOf(lay);
    std::map<Index, int> owner; // lattice point -> level of its active node
    for (int k = 0; k < static_cast<int>(g.levels.size()); ++k) {
      const Level3 &L = g.levels[k];
      gimp::forEachIndex<D>(L.n, [&](const Index &i) {
        if (!g.nodeActive(k, i)) return;
        Index u;
        for (int a = 0; a < D; ++a)
          u[a] = L.at(a, i[a]);
        EXPECT_EQ(owner.count(u), 0u) << lay.name << ": two active nodes at one point";
        owner[u] = k;
        // The active node is the finest level's whose closed box holds the point.
        for (int q = k + 1; q < static_cast<int>(g.levels.size()); ++q) {
          bool in = true;
          for (int a = 0; a < D; ++a)
            in = in && u[a] >= g.levels[q].lo[a] && u[a] <= g.levels[q].hi[a];
          EXPECT_FALSE(in) << lay.name << ": level " << k << " node inside level " << q;
        }
        // Zones: per axis and side the smallest width of the leaf cells there that lie in the
        // domain, computed here from the cells' centres in metres (0 when none does).
        double z[6];
        g.zonesOf(k, i, z);
        for (int ax = 0; ax < D; ++ax)
          for (int s = 0; s < 2; ++s) {
            double w = 0.0;
            for (int c = 0; c < 4; ++c) {
              double p[3];
              for (int a = 0, bit = 0; a < D; ++a) {
                const double off = a == ax ? (s ? 1 : -1) : ((c >> bit++) & 1 ? 1 : -1);
                p[a] = g.nodeCoordinate(k, a, i[a]) + 0.5 * off * g.hMin();
              }
              bool inDomain = true;
              for (int a = 0; a < D; ++a)
                inDomain = inDomain && p[a] > g.levels[0].box[a] && p[a] < g.levels[0].box[D + a];
              if (!inDomain) continue;
              const double h = g.levels[g.leafLevelAt(p)].h;
              w = w == 0.0 ? h : std::min(w, h);
            }
            const double expect = w;
            EXPECT_EQ(z[2 * ax + s], expect)
                << lay.name << ": level " << k << " node " << i[0] << "," << i[1] << "," << i[2]
                << " side " << 2 * ax + s;
          }
      });
    }
    // Every point of every level's node set carries an active node, of the finest level whose
    // closed box holds it; and activeNodes counts them.
    std::int64_t total = 0, missing = 0, wrongLevel = 0;
    for (int k = 0; k < static_cast<int>(g.levels.size()); ++k) {
      total += g.activeNodes(k);
      const Level3 &L = g.levels[k];
      gimp::forEachIndex<D>(L.n, [&](const Index &i) {
        Index u;
        for (int a = 0; a < D; ++a)
          u[a] = L.at(a, i[a]);
        int finest = 0;
        for (int q = 1; q < static_cast<int>(g.levels.size()); ++q) {
          bool in = true;
          for (int a = 0; a < D; ++a)
            in = in && u[a] >= g.levels[q].lo[a] && u[a] <= g.levels[q].hi[a];
          if (in) finest = q;
        }
        const auto it = owner.find(u);
        if (it == owner.end())
          ++missing;
        else if (it->second != finest)
          ++wrongLevel;
      });
    }
    EXPECT_EQ(missing, 0) << lay.name << ": node points without an active node";
    EXPECT_EQ(wrongLevel, 0) << lay.name << ": active node not of the finest level there";
    EXPECT_EQ(total, static_cast<std::int64_t>(owner.size())) << lay.name;
  }
}

// ---------------------------------------------------------------------------------------------
// 3. Partition of unity and linear reproduction of the 3D weights on the composite grid.

struct Identities {
  Worst unity, repro, gradSum, gradRepro, bounds;
  long particles = 0, straddle = 0, corner = 0, blockParticles = 0;
  long besideIrregular = 0; // block particles with a node not regular on both sides
  void reportSums() {
    EXPECT_WORST_LE(unity, 1e-12);
    EXPECT_WORST_LE(repro, 1e-12);
    EXPECT_WORST_LE(gradSum, 1e-10);
    EXPECT_WORST_LE(gradRepro, 1e-10);
    EXPECT_WORST_LE(bounds, 0.0);
  }
  void report(long total, bool refined) {
    EXPECT_WORST_LE(unity, 1e-12);
    EXPECT_WORST_LE(repro, 1e-12);
    EXPECT_WORST_LE(gradSum, 1e-10);
    EXPECT_WORST_LE(gradRepro, 1e-10);
    EXPECT_WORST_LE(bounds, 0.0);
    std::printf("  particles %ld: straddling two levels %ld, covering a box corner %ld\n",
                particles, straddle, corner);
    EXPECT_EQ(particles, total);
    if (!refined) return;
    EXPECT_GT(straddle, particles / 4);
    EXPECT_GT(corner, particles / 20);
  }
};

/// The grid's stencils of one particle summed as weightSums does (rows or a block, through
/// Stencils::forEach); `bad` counts entries on inactive, out-of-window or repeated nodes.
Sums stencilSums(const Grid3 &g, const Stencils3 &st, PetscInt p, const double *x, const double *l,
                 std::vector<PetscInt> &seen, long &bad, const Entries &ref, double &diff) {
  Sums s;
  Entries left = ref;
  // Gradients are compared on the weights' scale: times the particle's half-size (they reach
  // 1 / l).
  const double h0 = std::min({l[0], l[1], l[2]});
  st.forEach(p, [&](PetscInt nd, double W, const gimp::Vector<D> &G) {
    if (nd < 0 || nd >= g.nWindow || !g.active[nd] || seen[nd] == p) {
      ++bad;
      return;
    }
    seen[nd] = p;
    // The same weight and gradient as the lattice's (a node it left out has none).
    const auto it = left.find(nd);
    const std::array<double, 4> e = it == left.end() ? std::array<double, 4>{} : it->second;
    if (it != left.end()) left.erase(it);
    diff = std::max({diff, std::abs(W - e[0]), std::abs(G[0] - e[1]) * h0,
                     std::abs(G[1] - e[2]) * h0, std::abs(G[2] - e[3]) * h0});
    if (W == 0.0 && G.isZero()) return; // listed, but out of reach (counts as no node)
    ++s.nodes;
    s.w += W;
    s.lo = std::min(s.lo, W);
    s.hi = std::max(s.hi, W);
    for (int a = 0; a < D; ++a) {
      const double r = g.coordinates(a)[nd] - x[a];
      s.wr[a] += W * r;
      s.g[a] += G[a];
      for (int b = 0; b < D; ++b)
        s.gr[b][a] += G[b] * r;
    }
  });
  // Nodes the lattice has and the stencil left out.
  for (const auto &[nd, e] : left)
    diff = std::max(
        {diff, std::abs(e[0]), std::abs(e[1]) * h0, std::abs(e[2]) * h0, std::abs(e[3]) * h0});
  return s;
}

/// The identities of one particle's sums.
void record(Identities &id, const Sums &s, double h0, const std::function<std::string()> &where) {
  id.unity.update(std::abs(s.w - 1.0), where);
  id.repro.update(std::max({std::abs(s.wr[0]), std::abs(s.wr[1]), std::abs(s.wr[2])}) / h0, where);
  id.gradSum.update(std::max({std::abs(s.g[0]), std::abs(s.g[1]), std::abs(s.g[2])}) * h0, where);
  double gr = 0;
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b)
      gr = std::max(gr, std::abs(s.gr[a][b] - (a == b ? 1.0 : 0.0)));
  id.gradRepro.update(gr, where);
  id.bounds.update(std::max(-s.lo, s.hi - 1.0), where);
}

/// np random particles on one layout: the lattice's weights (products of Eq. 15 with each
/// node's zones, summed over every active node) and the grid's stencils, rows and blocks.
void checkLayout(const Layout &lay, long np, std::uint64_t seed, Identities &lattice,
                 Identities &rows, Identities &blocks, Worst &rowsVsLattice, Worst &badNodes) {
  const Lattice3 lat = latticeOf(lay);
  const Nodes tab(lat);
  Grid3 g;
  ASSERT_EQ(static_cast<int>(g.create(PETSC_COMM_SELF, kH0, boxesOf(lay))), 0);
  const double h0 = g.h0();
  const int K = static_cast<int>(g.levels.size());
  std::mt19937_64 rng(seed);
  std::vector<double> x(D * np), l(D * np);
  for (long p = 0; p < np; ++p)
    drawParticle(lat, rng, &x[D * p], &l[D * p]);
  Stencils3 sr, sb;
  ASSERT_TRUE(g.buildStencils(static_cast<PetscInt>(np), x.data(), l.data(), sr, false));
  ASSERT_TRUE(g.buildStencils(static_cast<PetscInt>(np), x.data(), l.data(), sb, true));
  std::vector<PetscInt> seenR(g.nWindow, -1), seenB(g.nWindow, -1);
  long nBlocks = 0, nBeside = 0;
  for (long p = 0; p < np; ++p) {
    const double *xp = &x[D * p], *lp = &l[D * p];
    // Statistics of what was drawn.
    const int q = lat.leafLevelAt(xp);
    bool straddles = false;
    for (int c = 0; c < 27 && !straddles; ++c) {
      double y[3];
      for (int a = 0, cc = c; a < D; ++a, cc /= 3)
        y[a] = xp[a] + 0.999 * (cc % 3 - 1) * lp[a];
      straddles = lat.leafLevelAt(y) != q;
    }
    lattice.straddle += straddles;
    bool corner = false;
    for (int k = 1; k < K && !corner; ++k)
      for (int c = 0; c < 8 && !corner; ++c) {
        bool in = true;
        for (int a = 0; a < D; ++a)
          in = in && std::abs(lat.levels[k].box[((c >> a) & 1 ? D : 0) + a] - xp[a]) < lp[a];
        corner = in;
      }
    lattice.corner += corner;
    ++lattice.particles;
    nBlocks += sb.isBlock(static_cast<PetscInt>(p));
    if (sb.isBlock(static_cast<PetscInt>(p))) { // a block with a box-face or domain-edge node
      bool irregular = false;
      sb.forEach(static_cast<PetscInt>(p), [&](PetscInt n, double, const gimp::Vector<3> &) {
        irregular = irregular || !g.regular[n];
      });
      nBeside += irregular;
    }

    Entries entries;
    const Sums ref = weightSums(lat, tab, xp, lp, &g, &entries);
    long bad = 0;
    double diffR = 0, diffB = 0;
    const Sums sumR =
        stencilSums(g, sr, static_cast<PetscInt>(p), xp, lp, seenR, bad, entries, diffR);
    const Sums sumB =
        stencilSums(g, sb, static_cast<PetscInt>(p), xp, lp, seenB, bad, entries, diffB);
    auto where = [&] {
      return lay.name + ": " +
             at({{"x", xp[0]},
                 {"y", xp[1]},
                 {"z", xp[2]},
                 {"lx", lp[0]},
                 {"ly", lp[1]},
                 {"lz", lp[2]},
                 {"sum", ref.w}});
    };
    record(lattice, ref, h0, where);
    record(rows, sumR, h0, where);
    record(blocks, sumB, h0, where);
    // Rows and blocks hold the lattice's weights and gradients, node by node.
    rowsVsLattice.update(std::max(diffR, diffB), where);
    badNodes.update(static_cast<double>(bad), where);
  }
  rows.particles += np;
  blocks.particles += np;
  blocks.blockParticles += nBlocks;
  blocks.besideIrregular += nBeside;
}

void checkLayouts(const std::vector<Layout> &layouts, long total, std::uint64_t seed,
                  bool refined = true) {
  const long per = total / static_cast<long>(layouts.size());
  Identities lattice, rows, blocks;
  Worst rowsVsLattice, badNodes;
  for (size_t k = 0; k < layouts.size(); ++k)
    checkLayout(layouts[k], k + 1 < layouts.size() ? per : total - per * (layouts.size() - 1),
                seed++, lattice, rows, blocks, rowsVsLattice, badNodes);
  std::printf(" the lattice's weights:\n");
  lattice.report(total, refined);
  std::printf(" the grid's stencils, rows:\n");
  rows.reportSums();
  std::printf(" the grid's stencils, blocks where a particle has one (%ld of %ld; %ld of them "
              "beside a box face or the domain's edge, a node of the block not regular on both "
              "sides):\n",
              blocks.blockParticles, total, blocks.besideIrregular);
  blocks.reportSums();
  EXPECT_GT(blocks.blockParticles, refined ? 0 : total / 20);
  // Blocks reach nodes whose zone differs from h on the side away from the particle.
  EXPECT_GT(blocks.besideIrregular, blocks.blockParticles / 20);
  EXPECT_WORST_LE(rowsVsLattice, 1e-13); // per node: |dw|, |d grad w| l
  EXPECT_WORST_LE(badNodes, 0.0);
}

TEST(Grid3D, TwoLevelIdentities) {
  checkLayouts(twoLevelLayouts(), 50000, 0x3d000001);
}

TEST(Grid3D, ThreeLevelIdentities) {
  checkLayouts(threeLevelLayouts(), 100000, 0x3d000101);
}

TEST(Grid3D, CrackedBlocksEqualRows) {
  long blocks = 0, blocksWithout = 0, besideCracked = 0, readdressed = 0, compared = 0;
  Worst weight, gradient;
  // Two and three levels with room for blocks away from the borders and the crack.
  const std::vector<Layout> layouts = {
      {"two levels r=2", {12, 10, 14}, {{{3, 2, 4, 9, 8, 10}, 2}}},
      {"three levels r=2,3", {12, 10, 14}, {{{2, 2, 3, 10, 8, 11}, 2}, {{3, 3, 5, 7, 7, 9}, 3}}},
      {"fine box on the domain face r=3", {10, 10, 14}, {{{0, 2, 4, 5, 8, 10}, 3}}}};
  for (const Layout &lay : layouts) {
    const Lattice3 lat = latticeOf(lay);
    const auto &Dm = lat.levels[0].box;
    double c[3], w[3];
    for (int a = 0; a < D; ++a) {
      c[a] = 0.5 * (Dm[a] + Dm[D + a]);
      w[a] = Dm[D + a] - Dm[a];
    }
    // A tilted quadrilateral through the middle, from outside the domain's left face, and the
    // part of its plane ahead of it where it may grow.
    const double zc = c[2] + 0.013 * w[2];
    auto plane = [&](double x, double y) {
      return std::array<double, 3>{x, y, zc + 0.11 * (x - c[0]) + 0.07 * (y - c[1])};
    };
    const double xa = Dm[0] - 0.1 * w[0], xb = c[0] + 0.07 * w[0], ya = c[1] - 0.29 * w[1],
                 yb = c[1] + 0.31 * w[1];
    gimp::CrackSurface crack =
        gimp::cracks::makeSurface({plane(xa, ya), plane(xb, ya), plane(xb, yb), plane(xa, yb)});
    crack.front = {1, 1, 1, 1};
    Grid3 g;
    g.crackReserveSurfaces.push_back(gimp::cracks::makeSurface(
        {plane(xb, ya), plane(xb + 0.2 * w[0], ya), plane(xb + 0.2 * w[0], yb), plane(xb, yb)}));
    ASSERT_EQ(static_cast<int>(g.create(PETSC_COMM_SELF, kH0, boxesOf(lay), {crack})), 0);
    ASSERT_GT(g.nSlots, g.nWindow) << lay.name;
    std::mt19937_64 rng(0x3dc0ac00);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    const long np = 6000;
    std::vector<double> x(D * np), l(D * np);
    double lmax = 0;
    for (long p = 0; p < np; ++p) {
      // Anywhere in the domain, of up to a fifth of its leaf cell (so that most keep blocks away
      // from the crack and the level borders).
      for (int a = 0; a < D; ++a)
        x[D * p + a] = Dm[a] + uni(rng) * (Dm[D + a] - Dm[a]);
      const double h = lat.levels[lat.leafLevelAt(&x[D * p])].h;
      for (int a = 0; a < D; ++a) {
        l[D * p + a] = h * (0.05 + 0.15 * uni(rng));
        lmax = std::max(lmax, l[D * p + a]);
      }
    }
    // The same particles on the grid without the crack: which keep blocks there.
    Grid3 plain;
    ASSERT_EQ(static_cast<int>(plain.create(PETSC_COMM_SELF, kH0, boxesOf(lay))), 0);
    Stencils3 free;
    ASSERT_TRUE(
        plain.buildStencils(static_cast<PetscInt>(np), x.data(), l.data(), free, true, true));
    g.markLiveCracks({crack}, g.liveReachFor(lmax));
    Stencils3 rows, compact;
    ASSERT_TRUE(g.buildStencils(static_cast<PetscInt>(np), x.data(), l.data(), rows, false));
    ASSERT_TRUE(
        g.buildStencils(static_cast<PetscInt>(np), x.data(), l.data(), compact, true, true));
    for (long p = 0; p < np; ++p)
      for (PetscInt e = rows.start[p]; e < rows.start[p + 1]; ++e) {
        const PetscInt n = rows.node[e];
        const double X[3] = {g.X[n], g.Y[n], g.Z[n]};
        if (g.crackSlot[n] >= 0 && gimp::cracks::crossing(crack, &x[D * p], X) != 0)
          rows.node[e] = g.crackSlot[n];
      }
    gimp::cracks::assignFields<D>(g, {crack}, static_cast<PetscInt>(np), x.data(), compact);
    for (long p = 0; p < np; ++p) {
      std::map<PetscInt, std::array<double, 4>> r, b;
      const auto collect = [&](const Stencils3 &s, std::map<PetscInt, std::array<double, 4>> &m) {
        s.forEach(p, [&](PetscInt slot, double wt, const gimp::Vector<D> &gr) {
          auto &e = m[slot];
          e[0] += wt;
          for (int a = 0; a < D; ++a)
            e[1 + a] += gr[a];
        });
      };
      collect(rows, r);
      collect(compact, b);
      const auto where = [&] {
        return lay.name + ": " + at({{"x", x[D * p]}, {"y", x[D * p + 1]}, {"z", x[D * p + 2]}});
      };
      // A node either form lists with weight 0 (or 1e-30) and the other leaves out reads as 0.
      const auto diff = [&](const auto &u, const auto &v) {
        for (const auto &[slot, e] : u) {
          const auto it = v.find(slot);
          const std::array<double, 4> f = it == v.end() ? std::array<double, 4>{} : it->second;
          weight.update(std::abs(e[0] - f[0]), where);
          double dg = 0;
          for (int a = 0; a < D; ++a)
            dg = std::max(dg, std::abs(e[1 + a] - f[1 + a]));
          gradient.update(dg * kH0, where);
        }
      };
      diff(r, b);
      diff(b, r);
      blocks += compact.isBlock(p);
      blocksWithout += free.isBlock(p);
      bool second = false, cracked = false;
      for (const auto &[slot, e] : r) {
        second = second || slot >= g.nWindow;
        cracked = cracked || (slot < g.nWindow && g.crackSlot[slot] >= 0);
      }
      readdressed += second;
      besideCracked += compact.isBlock(p) && cracked;
      ++compared;
    }
  }
  std::printf("  particles %ld: blocks %ld (%ld without the crack; %ld beside a cracked node "
              "the crack does not reach), with a second field %ld\n",
              compared, blocks, blocksWithout, besideCracked, readdressed);
  EXPECT_WORST_LE(weight, 1e-14);
  EXPECT_WORST_LE(gradient, 1e-12);
  EXPECT_GT(blocks, compared / 20);
  EXPECT_GT(blocksWithout - blocks, compared / 100); // the crack's neighbours keep rows
  EXPECT_GT(besideCracked, compared / 100);          // the reserve and the reach's edge do not
  EXPECT_GT(readdressed, compared / 100);
}

TEST(Grid3D, LevelBlocksEqualRows) {
  // Particles that two levels reach, or whose level's nodes are not all regular, keep level
  // blocks (Stencils::levelBlocks) instead of rows: the same nodes in the same order, each with
  // the rows' weight and gradient to round-off, in less room. Fails if a level block drops,
  // adds or moves a node (a masked node, a wrong first slot or stride), takes a factor from the
  // wrong node, or if no particle takes the path.
  Worst weight, gradient;
  long particles = 0, withLevels = 0, twoLevels = 0, mismatched = 0;
  size_t rowBytes = 0, blockBytes = 0;
  std::uint64_t seed = 0x3d1eb10c;
  for (const Layout &lay : threeLevelLayouts()) {
    const Lattice3 lat = latticeOf(lay);
    Grid3 g;
    ASSERT_EQ(static_cast<int>(g.create(PETSC_COMM_SELF, kH0, boxesOf(lay))), 0);
    std::mt19937_64 rng(seed++);
    const long np = 4000;
    std::vector<double> x(D * np), l(D * np);
    for (long p = 0; p < np; ++p)
      drawParticle(lat, rng, &x[D * p], &l[D * p]);
    Stencils3 rows, compact;
    ASSERT_TRUE(g.buildStencils(static_cast<PetscInt>(np), x.data(), l.data(), rows, false));
    ASSERT_TRUE(g.buildStencils(static_cast<PetscInt>(np), x.data(), l.data(), compact, true));
    for (long p = 0; p < np; ++p) {
      ++particles;
      if (!compact.isLevels(p)) continue;
      ++withLevels;
      EXPECT_EQ(compact.start[p], compact.start[p + 1]) << "a level-block particle keeps rows";
      int blocks = 0;
      for (PetscInt i = compact.levelOf[p];; ++i) {
        ++blocks;
        if (compact.levelBlocks[i].last) break;
      }
      twoLevels += blocks > 1;
      blockBytes += blocks * sizeof(gimp::LevelBlock<D>);
      rowBytes += (rows.start[p + 1] - rows.start[p]) * (sizeof(PetscInt) + 2 * D * sizeof(double));
      PetscInt e = rows.start[p];
      const auto where = [&] {
        return lay.name + ": " + at({{"x", x[D * p]}, {"y", x[D * p + 1]}, {"z", x[D * p + 2]}});
      };
      compact.forEach(p, [&](PetscInt slot, double wt, const gimp::Vector<D> &gr) {
        if (e >= rows.start[p + 1] || rows.node[e] != slot) {
          ++mismatched;
          return;
        }
        weight.update(std::abs(wt - rows.weight(e)), where);
        const gimp::Vector<D> rg = rows.gradient(e);
        double dg = 0;
        for (int a = 0; a < D; ++a)
          dg = std::max(dg, std::abs(gr[a] - rg[a]));
        gradient.update(dg * kH0, where);
        ++e;
      });
      mismatched += rows.start[p + 1] - e; // (rows left over)
    }
  }
  std::printf("  particles %ld: with level blocks %ld (two levels %ld), %zu bytes against %zu "
              "in rows\n",
              particles, withLevels, twoLevels, blockBytes, rowBytes);
  EXPECT_EQ(mismatched, 0);
  EXPECT_WORST_LE(weight, 1e-15);
  EXPECT_WORST_LE(gradient, 1e-13);
  EXPECT_GT(withLevels, particles / 20);
  EXPECT_GT(twoLevels, particles / 50);
  EXPECT_LT(2 * blockBytes, rowBytes);
  // 2D keeps rows there: a level's fewest entries (4) take less room than a level block.
  EXPECT_FALSE(gimp::Stencils<2>::kLevelBlocks);
  EXPECT_TRUE(gimp::Stencils<3>::kLevelBlocks);
}

TEST(Grid3D, NodePatternsEqualNodeReads) {
  // With patterns (the rate classes' builds) appendNodes reads each candidate box's nodes once
  // (Grid::NodePattern) and each particle's entries axis by axis: the same rows and level blocks,
  // bit for bit, as reading the nodes for every particle, in a first build (the patterns made)
  // and a second (the patterns kept), as rows and as level blocks; then into the stencils of the
  // last build again, which read each particle's patterns of that build before the table, with
  // the particles where they were and moved by a little (some of them to other boxes). One grid
  // serves every layout in turn (cleared and made again, as a regrid does), and one set of
  // stencils every build, so patterns kept from the last layout would show. Fails if a pattern
  // drops or adds a node, takes a factor from the wrong zones or index, or outlives its grid.
  long particles = 0, levelParticles = 0, rowEntries = 0;
  std::uint64_t seed = 0x3d0a77e5;
  Grid3 g;
  Stencils3 carried; // (every build with patterns after the first of a layout: see above)
  const auto sameBlocks = [](const gimp::LevelBlock<D> &a, const gimp::LevelBlock<D> &b) {
    return std::memcmp(a.w, b.w, sizeof a.w) == 0 && std::memcmp(a.g, b.g, sizeof a.g) == 0 &&
           a.mask == b.mask && a.base == b.base && a.stride[0] == b.stride[0] &&
           a.stride[1] == b.stride[1] && std::memcmp(a.n, b.n, sizeof a.n) == 0 && a.last == b.last;
  };
  for (const Layout &lay : threeLevelLayouts()) {
    const Lattice3 lat = latticeOf(lay);
    g.clear();
    ASSERT_EQ(static_cast<int>(g.create(PETSC_COMM_SELF, kH0, boxesOf(lay))), 0);
    std::mt19937_64 rng(seed++);
    const long np = 3000;
    std::vector<double> x(D * np), l(D * np);
    for (long p = 0; p < np; ++p)
      drawParticle(lat, rng, &x[D * p], &l[D * p]);
    const double nudge = 0.3 * lat.levels.back().h; // (the last pass's largest move)
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    for (const bool compact : {false, true}) {
      Stencils3 read;
      ASSERT_TRUE(g.buildStencils(np, x.data(), l.data(), read, compact, false, false));
      for (int pass = 0; pass < 4; ++pass) {
        if (pass == 3) { // every particle moved by up to `nudge` along each axis, in the domain
          const auto &Dm = lat.levels[0].box;
          for (long p = 0; p < np; ++p)
            for (int a = 0; a < D; ++a)
              x[D * p + a] = std::clamp(x[D * p + a] + nudge * uni(rng), Dm[a] + l[D * p + a],
                                        Dm[D + a] - l[D * p + a]);
          ASSERT_TRUE(g.buildStencils(np, x.data(), l.data(), read, compact, false, false));
        }
        Stencils3 fresh;
        Stencils3 &kept = pass < 2 ? fresh : carried;
        ASSERT_TRUE(g.buildStencils(np, x.data(), l.data(), kept, compact, false, true));
        const std::string where = lay.name + (compact ? ", level blocks" : ", rows") +
                                  (pass == 0   ? ", patterns made"
                                   : pass == 1 ? ", patterns kept"
                                   : pass == 2 ? ", the last build's patterns"
                                               : ", the last build's patterns, moved");
        for (long p = 0; p <= np; ++p)
          ASSERT_EQ(read.start[p], kept.start[p]) << where << ", particle " << p;
        const PetscInt m = read.start[np];
        for (PetscInt e = 0; e < m; ++e) {
          ASSERT_EQ(read.node[e], kept.node[e]) << where << ", entry " << e;
          for (int a = 0; a < D; ++a) {
            ASSERT_EQ(read.w[a][e], kept.w[a][e]) << where << ", entry " << e;
            ASSERT_EQ(read.g[a][e], kept.g[a][e]) << where << ", entry " << e;
          }
        }
        ASSERT_EQ(read.nLevelBlocks, kept.nLevelBlocks) << where;
        for (PetscInt b = 0; b < read.nLevelBlocks; ++b)
          ASSERT_TRUE(sameBlocks(read.levelBlocks[b], kept.levelBlocks[b]))
              << where << ", level block " << b;
        for (long p = 0; p < np && compact; ++p)
          ASSERT_EQ(read.isLevels(p), kept.isLevels(p)) << where << ", particle " << p;
        if (pass == 0) {
          rowEntries += m;
          if (compact)
            for (long p = 0; p < np; ++p)
              levelParticles += read.isLevels(p);
        }
      }
    }
    particles += np;
  }
  std::printf("  particles %ld: %ld with level blocks, %ld row entries\n", particles,
              levelParticles, rowEntries);
  EXPECT_GT(levelParticles, particles / 20); // (the path is taken)
}

TEST(Grid3D, UniformIdentities) {
  checkLayouts({{"uniform", {6, 5, 4}, {}}}, 20000, 0x3d000201, false);
}

// ---------------------------------------------------------------------------------------------
// 4. Ranks: on any number of ranks (ctest runs this on two) the 3D decomposition, the windows
//    and their scatter give the one-rank answer. Every rank draws the same particles; each
//    spreads the mass and momentum of those it owns onto its window (P2G), the windows are
//    summed into the composite Vec and read back, and each particle's velocity is interpolated
//    from the nodes (G2P). A one-rank grid (PETSC_COMM_SELF) on the same layout does the same
//    with every particle.

/// P2G of mass and momentum, the global sum, and G2P of the nodal velocity at the particles
/// `mine`; returns the velocities (3 per particle of `mine`) and the total momentum.
std::vector<double> roundTrip(const Grid3 &g, MPI_Comm comm, const std::vector<double> &x,
                              const std::vector<double> &l, const std::vector<double> &m,
                              const std::vector<double> &v, const std::vector<long> &mine,
                              double total[3]) {
  const PetscInt n = static_cast<PetscInt>(mine.size());
  std::vector<double> xs(D * n), ls(D * n);
  for (PetscInt k = 0; k < n; ++k)
    for (int a = 0; a < D; ++a) {
      xs[D * k + a] = x[D * mine[k] + a];
      ls[D * k + a] = l[D * mine[k] + a];
    }
  Stencils3 st;
  EXPECT_TRUE(g.buildStencils(n, xs.data(), ls.data(), st, true));
  Vec wm, wp, gm, gp;
  EXPECT_EQ(static_cast<int>(g.createWindowVec(&wm)), 0);
  EXPECT_EQ(static_cast<int>(g.createWindowVec(&wp)), 0);
  EXPECT_EQ(static_cast<int>(DMCreateGlobalVector(g.dm, &gm)), 0);
  EXPECT_EQ(static_cast<int>(VecDuplicate(gm, &gp)), 0);
  PetscScalar *am, *ap;
  VecZeroEntries(wm);
  VecZeroEntries(wp);
  VecGetArray(wm, &am);
  VecGetArray(wp, &ap);
  for (PetscInt k = 0; k < n; ++k)
    st.forEach(k, [&](PetscInt nd, double W, const gimp::Vector<D> &) {
      const long p = mine[k];
      for (int a = 0; a < D; ++a) {
        am[D * nd + a] += W * m[p];
        ap[D * nd + a] += W * m[p] * v[D * p + a];
      }
    });
  VecRestoreArray(wm, &am);
  VecRestoreArray(wp, &ap);
  VecZeroEntries(gm);
  VecZeroEntries(gp);
  EXPECT_EQ(static_cast<int>(g.addFromWindow(wm, gm)), 0);
  EXPECT_EQ(static_cast<int>(g.addFromWindow(wp, gp)), 0);
  // Total momentum per axis: every level's part of the composite Vec holds D values per node.
  {
    PetscInt nloc = 0;
    const PetscScalar *c;
    VecGetLocalSize(gp, &nloc);
    VecGetArrayRead(gp, &c);
    double local[3] = {0, 0, 0};
    for (PetscInt i = 0; i < nloc; ++i)
      local[i % D] += c[i];
    VecRestoreArrayRead(gp, &c);
    MPI_Allreduce(local, total, D, MPI_DOUBLE, MPI_SUM, comm);
  }
  EXPECT_EQ(static_cast<int>(g.toWindow(gm, wm)), 0);
  EXPECT_EQ(static_cast<int>(g.toWindow(gp, wp)), 0);
  const PetscScalar *cm, *cp;
  VecGetArrayRead(wm, &cm);
  VecGetArrayRead(wp, &cp);
  std::vector<double> out(D * n, 0.0);
  for (PetscInt k = 0; k < n; ++k)
    st.forEach(k, [&](PetscInt nd, double W, const gimp::Vector<D> &) {
      if (cm[D * nd] <= 0) return;
      for (int a = 0; a < D; ++a)
        out[D * k + a] += W * cp[D * nd + a] / cm[D * nd + a];
    });
  VecRestoreArrayRead(wm, &cm);
  VecRestoreArrayRead(wp, &cp);
  VecDestroy(&wm);
  VecDestroy(&wp);
  VecDestroy(&gm);
  VecDestroy(&gp);
  return out;
}

TEST(Grid3DMpi, RanksGiveTheOneRankAnswer) {
  MPI_Comm world = PETSC_COMM_WORLD;
  PetscMPIInt size = 1, rank = 0;
  MPI_Comm_size(world, &size);
  MPI_Comm_rank(world, &rank);
  for (const Layout &lay : {threeLevelLayouts()[0], threeLevelLayouts()[8]}) {
    Grid3 gw, gs;
    ASSERT_EQ(static_cast<int>(gw.create(world, kH0, boxesOf(lay))), 0);
    {
      // The one-rank grid without the rank layout options (-da_processors_x/y/z) the world's
      // may have been given.
      std::vector<std::pair<std::string, std::string>> saved;
      for (const char *o : {"-da_processors_x", "-da_processors_y", "-da_processors_z"}) {
        char val[64];
        PetscBool set = PETSC_FALSE;
        PetscOptionsGetString(nullptr, nullptr, o, val, sizeof(val), &set);
        if (!set) continue;
        saved.emplace_back(o, val);
        PetscOptionsClearValue(nullptr, o);
      }
      ASSERT_EQ(static_cast<int>(gs.create(PETSC_COMM_SELF, kH0, boxesOf(lay))), 0);
      for (const auto &[o, val] : saved)
        PetscOptionsSetValue(nullptr, o.c_str(), val.c_str());
    }
    const Lattice3 lat = latticeOf(lay);
    const long np = 6000;
    std::mt19937_64 rng(0x3d0003);
    std::vector<double> x(D * np), l(D * np), m(np), v(D * np);
    for (long p = 0; p < np; ++p) {
      drawParticle(lat, rng, &x[D * p], &l[D * p]);
      m[p] = 1.0 + x[D * p] * x[D * p];
      for (int a = 0; a < D; ++a)
        v[D * p + a] = std::sin(3.0 * x[D * p + a] + a) + 0.5 * x[D * p + (a + 1) % D];
    }
    // Ownership: every particle has one owner rank, the same the owned boxes say.
    std::vector<long> mine, all(np);
    double box[6];
    gw.ownedBox(rank, box);
    long outside = 0;
    for (long p = 0; p < np; ++p) {
      all[p] = p;
      if (gw.ownerOf(&x[D * p]) != rank) continue;
      mine.push_back(p);
      for (int a = 0; a < D; ++a)
        outside += x[D * p + a] < box[a] || x[D * p + a] >= box[D + a];
    }
    EXPECT_EQ(outside, 0) << lay.name << ": owned particles outside the rank's box";
    long owned = static_cast<long>(mine.size()), sum = 0;
    MPI_Allreduce(&owned, &sum, 1, MPI_LONG, MPI_SUM, world);
    EXPECT_EQ(sum, np) << lay.name;
    if (size > 1) {
      EXPECT_LT(owned, np) << lay.name << ": one rank owns every particle";
    }

    double tw[3], ts[3];
    const std::vector<double> vw = roundTrip(gw, world, x, l, m, v, mine, tw);
    const std::vector<double> vs = roundTrip(gs, PETSC_COMM_SELF, x, l, m, v, all, ts);
    double err = 0, scale = 0;
    for (size_t k = 0; k < mine.size(); ++k)
      for (int a = 0; a < D; ++a) {
        err = std::max(err, std::abs(vw[D * k + a] - vs[D * mine[k] + a]));
        scale = std::max(scale, std::abs(vs[D * mine[k] + a]));
      }
    double errAll = 0, scaleAll = 0; // (a rank may own no particle)
    MPI_Allreduce(&err, &errAll, 1, MPI_DOUBLE, MPI_MAX, world);
    MPI_Allreduce(&scale, &scaleAll, 1, MPI_DOUBLE, MPI_MAX, world);
    scale = scaleAll;
    std::printf("  %s on %d ranks: G2P velocities differ from one rank's by %.3g (scale %.3g); "
                "momentum %.17g %.17g %.17g\n",
                lay.name.c_str(), size, errAll, scale, tw[0], tw[1], tw[2]);
    EXPECT_LE(errAll, 1e-13 * scale) << lay.name;
    for (int a = 0; a < D; ++a) {
      EXPECT_NEAR(tw[a], ts[a], 1e-12 * std::abs(ts[a])) << lay.name << " momentum " << a;
      double direct = 0; // the particles' own momentum
      for (long p = 0; p < np; ++p)
        direct += m[p] * v[D * p + a];
      EXPECT_NEAR(tw[a], direct, 1e-12 * std::abs(direct)) << lay.name << " momentum " << a;
    }
  }
}

/// The moves of levels from, from + 1, ... alone (Grid::toWindow, fromWindow with `from`): the
/// full move's values there, nothing touched before them (the per-level step's nodal sums).
TEST(Grid3DMpi, LevelMovesEqualTheFullMove) {
  MPI_Comm world = PETSC_COMM_WORLD;
  PetscMPIInt rank = 0;
  MPI_Comm_rank(world, &rank);
  Grid3 g;
  ASSERT_EQ(static_cast<int>(g.create(world, kH0, boxesOf(threeLevelLayouts()[0]))), 0);
  const int K = static_cast<int>(g.levels.size());
  ASSERT_EQ(K, 3);
  Vec w, wf, ws, gf, gs;
  ASSERT_EQ(static_cast<int>(g.createWindowVec(&w)), 0);
  VecDuplicate(w, &wf);
  VecDuplicate(w, &ws);
  ASSERT_EQ(static_cast<int>(DMCreateGlobalVector(g.dm, &gf)), 0);
  VecDuplicate(gf, &gs);
  PetscInt nw = 0, ng = 0;
  VecGetLocalSize(w, &nw);
  VecGetLocalSize(gf, &ng);
  EXPECT_EQ(g.localLevelStart(0), 0);
  EXPECT_EQ(g.windowLevelStart(0), 0);
  PetscScalar *a;
  VecGetArray(w, &a); // integers: every sum is exact, whatever its order
  for (PetscInt i = 0; i < nw; ++i)
    a[i] = static_cast<double>((i * 7 + 13 * rank) % 101) - 50.0;
  VecRestoreArray(w, &a);
  VecGetArray(gf, &a);
  for (PetscInt i = 0; i < ng; ++i)
    a[i] = static_cast<double>((i * 11 + 5 * rank) % 97) - 40.0;
  VecRestoreArray(gf, &a);
  VecCopy(gf, gs);
  for (int from = 1; from < K; ++from) {
    const PetscInt g0 = g.localLevelStart(from), w0 = g.windowLevelStart(from);
    EXPECT_GE(g0, g.localLevelStart(from - 1));
    EXPECT_EQ(w0, D * g.levels[from].offset);
    // Forward: the full move's window values from w0 on; the sentinel before.
    VecSet(wf, 0.0);
    VecSet(ws, 7.5);
    ASSERT_EQ(static_cast<int>(g.toWindow(gf, wf)), 0);
    ASSERT_EQ(static_cast<int>(g.toWindow(gs, ws, from)), 0);
    const PetscScalar *f, *s;
    long bad = 0;
    VecGetArrayRead(wf, &f);
    VecGetArrayRead(ws, &s);
    for (PetscInt i = 0; i < nw; ++i)
      bad += i < w0 ? s[i] != 7.5 : s[i] != f[i];
    VecRestoreArrayRead(ws, &s);
    VecRestoreArrayRead(wf, &f);
    // Reverse (added): the full sum of every rank's window from g0 on; the sentinel before.
    Vec sf, ss;
    VecDuplicate(gf, &sf);
    VecDuplicate(gf, &ss);
    VecSet(sf, 0.0);
    VecSet(ss, 0.0);
    ASSERT_EQ(static_cast<int>(g.addFromWindow(w, sf)), 0);
    VecGetArray(ss, &a);
    for (PetscInt i = 0; i < g0; ++i)
      a[i] = -3.25;
    VecRestoreArray(ss, &a);
    ASSERT_EQ(static_cast<int>(g.addFromWindow(w, ss, from)), 0);
    VecGetArrayRead(sf, &f);
    VecGetArrayRead(ss, &s);
    for (PetscInt i = 0; i < ng; ++i)
      bad += i < g0 ? s[i] != -3.25 : s[i] != f[i];
    VecRestoreArrayRead(ss, &s);
    VecRestoreArrayRead(sf, &f);
    VecDestroy(&sf);
    VecDestroy(&ss);
    long badAll = 0;
    MPI_Allreduce(&bad, &badAll, 1, MPI_LONG, MPI_SUM, world);
    EXPECT_EQ(badAll, 0) << "levels from " << from;
  }
  for (Vec *v : {&w, &wf, &ws, &gf, &gs})
    VecDestroy(v);
}

// ---------------------------------------------------------------------------------------------
// 5. Bad layouts.

TEST(Grid3D, BadLayoutsRejected) {
  auto message = [](const std::vector<gimp::LevelBox<D>> &b) {
    try {
      Lattice3 g;
      g.setLevels(1.0, b);
    } catch (const gimp::InputError &e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const gimp::LevelBox<D> dom{{0, 0, 0, 4, 4, 4}, 1};
  // A z corner off the parent's lines.
  EXPECT_NE(message({dom, {{1, 1, 1.5, 3, 3, 3}, 2}})
                .find("-gimp_level1_box 1,1,1.5,3,3,3: "
                      "corner coordinate 1.5 is not on a "
                      "grid line of level 0"),
            std::string::npos);
  // Not nested in z.
  EXPECT_NE(message({dom, {{1, 1, 1, 3, 3, 3}, 2}, {{1, 1, 0.5, 2, 2, 2}, 2}})
                .find("(levels must be nested)"),
            std::string::npos);
  // Empty in z.
  EXPECT_NE(message({dom, {{1, 1, 2, 3, 3, 2}, 2}}).find("needs x1 > x0, y1 > y0 and z1 > z0"),
            std::string::npos);
  EXPECT_EQ(message({dom, {{1, 1, 1, 3, 3, 3}, 2}, {{1, 1, 1, 2, 2, 1.5}, 2}}), "accepted");
}

} // namespace

TEST(Grid3D, BalancedRanges) {
  // Cells 0..7 between nodes 0..8; the work sits in cells 4 and 5.
  const std::vector<double> work = {1, 1, 1, 1, 10, 10, 1, 1};
  const std::vector<PetscInt> two = gimp::balancedRanges(work, 9, 2);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0] + two[1], 9);
  EXPECT_EQ(two[0], 5); // cells 0..4 (14) against 5..7 (12): the nearest split of 26
  // Every rank at least one node, whatever the work.
  const std::vector<PetscInt> many = gimp::balancedRanges({0, 0, 0, 100}, 5, 4);
  PetscInt sum = 0;
  for (PetscInt r : many) {
    EXPECT_GE(r, 1);
    sum += r;
  }
  EXPECT_EQ(sum, 5);
  // Even work gives the even split.
  const std::vector<PetscInt> even = gimp::balancedRanges(std::vector<double>(8, 1.0), 9, 2);
  EXPECT_EQ(even[0], 4);
  EXPECT_EQ(even[1], 5);
}
