// Unit tests of the composite lattice in 3D (include/gimp/grid/lattice.hpp with D = 3): nested
// uniform levels with integer ratios, active nodes, influence zones [Lx-, Lx+, Ly-, Ly+, Lz-,
// Lz+] and the GIMP weights built from them as products of the 1D weights of Eq. 15.
//
//   1. A hand-checked grid: named nodes' activity and zones (a face, an edge and a corner of a
//      fine box, a node on the domain's face).
//   2. Every location carries exactly one active node, whose zones are the widths of the leaf
//      cells next to it (per axis and side, the smallest of the four cells there).
//   3. Partition of unity, linear reproduction and their derivatives at 1e5 random particles
//      over 2- and 3-level layouts with ratios 2, 3 and 4 (boxes in the middle, on a parent's
//      face, edge and corner, on the domain's faces, a one-cell slab, coinciding boxes).
//   4. Badly nested 3D layouts are rejected naming the option and the reason.
//
// All random sampling uses a fixed-seed std::mt19937_64, so every run checks the same points.
#include "gimp/grid/lattice.hpp"
#include "gimp/grid/shape.hpp"

#include "test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using gimp::test::at;
using gimp::test::Worst;

constexpr int D = 3;
using Lattice3 = gimp::LatticeT<D>;
using Level3 = gimp::LevelT<D>;
using Box3 = gimp::BoxOf<D>;
using Index = gimp::LatticeIndex<D>;

// Domain origin and level-0 cell size that are not binary fractions, so node coordinates carry
// round-off as in real scenes.
constexpr double kX0 = -1.3, kY0 = 0.7, kZ0 = 2.1, kH0 = 0.37;

/// A refined box in level-0 cells from the origin (fractions where they fall on the parent's
/// lines) and its ratio.
struct BoxSpec {
  std::array<double, 6> c;
  int ratio;
};
struct Layout {
  std::string name;
  std::array<int, 3> cells; // level-0 cells of the domain per axis
  std::vector<BoxSpec> boxes;
};

Lattice3 latticeOf(const Layout &lay) {
  const double o[3] = {kX0, kY0, kZ0};
  std::vector<gimp::LevelBox<D>> b(1);
  for (int a = 0; a < D; ++a) {
    b[0].box[a] = o[a];
    b[0].box[D + a] = o[a] + lay.cells[a] * kH0;
  }
  for (const BoxSpec &s : lay.boxes) {
    gimp::LevelBox<D> L;
    for (int d = 0; d < 2 * D; ++d)
      L.box[d] = o[d % D] + s.c[d] * kH0;
    L.ratio = s.ratio;
    b.push_back(L);
  }
  Lattice3 g;
  g.setLevels(kH0, b);
  return g;
}

std::vector<Layout> twoLevelLayouts() {
  std::vector<Layout> v;
  for (int r : {2, 3, 4}) {
    const std::string s = " r=" + std::to_string(r);
    v.push_back({"middle" + s, {6, 5, 4}, {{{2, 1, 1, 4, 3, 3}, r}}});
    v.push_back({"domain face" + s, {6, 5, 4}, {{{0, 1, 1, 2, 4, 3}, r}}});
    v.push_back({"domain corner" + s, {6, 5, 4}, {{{4, 3, 2, 6, 5, 4}, r}}});
    v.push_back({"one cell" + s, {6, 5, 4}, {{{3, 2, 1, 4, 3, 2}, r}}});
  }
  return v;
}

/// 3-level layouts (level-2 box in level-1 cells f = 1 / r1): in the middle of level 1, on one
/// of its faces, in its corner (three faces), along a domain edge with all levels sharing it, a
/// one-cell slab across level 1, and coinciding with level 1.
std::vector<Layout> threeLevelLayouts() {
  std::vector<Layout> v;
  const std::pair<int, int> ratios[] = {{2, 2}, {3, 3}, {4, 4}, {2, 4}, {4, 3}, {3, 2}};
  for (const auto &[r1, r2] : ratios) {
    const double f = 1.0 / r1;
    const std::string s = " r=" + std::to_string(r1) + "," + std::to_string(r2);
    const BoxSpec mid{{1, 1, 1, 5, 4, 3}, r1};
    v.push_back({"middle" + s, {6, 5, 4}, {mid, {{2 + f, 2, 2 - f, 4, 3 - f, 2 + f}, r2}}});
    v.push_back({"parent face" + s, {6, 5, 4}, {mid, {{1, 2, 1 + f, 2 + f, 3, 2}, r2}}});
    v.push_back({"parent corner" + s, {6, 5, 4}, {mid, {{4 - f, 3, 2, 5, 4, 3}, r2}}});
    v.push_back(
        {"domain edge" + s, {6, 5, 4}, {{{0, 0, 1, 3, 5, 4}, r1}, {{0, 2, 2, 2, 5, 4}, r2}}});
    v.push_back({"slab" + s, {6, 5, 4}, {mid, {{3, 1, 1, 3 + f, 4, 3}, r2}}});
    v.push_back({"coincident" + s, {6, 5, 4}, {mid, mid}});
    v.back().boxes[1].ratio = r2;
  }
  return v;
}

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

Sums weightSums(const Lattice3 &g, const Nodes &tab, const double *x, const double *l) {
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

TEST(Lattice3D, NamedNodes) {
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

TEST(Lattice3D, OneActiveNodePerLocation) {
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
    // Every lattice point on some level's node set is covered exactly once.
    std::int64_t total = 0;
    for (int k = 0; k < static_cast<int>(g.levels.size()); ++k)
      total += g.activeNodes(k);
    EXPECT_EQ(total, static_cast<std::int64_t>(owner.size())) << lay.name;
  }
}

// ---------------------------------------------------------------------------------------------
// 3. Partition of unity and linear reproduction of the 3D weights on the composite grid.

struct Identities {
  Worst unity, repro, gradSum, gradRepro, bounds;
  long particles = 0, straddle = 0, corner = 0;
  void report(long total) {
    EXPECT_WORST_LE(unity, 1e-12);
    EXPECT_WORST_LE(repro, 1e-12);
    EXPECT_WORST_LE(gradSum, 1e-10);
    EXPECT_WORST_LE(gradRepro, 1e-10);
    EXPECT_WORST_LE(bounds, 0.0);
    std::printf("  particles %ld: straddling two levels %ld, covering a box corner %ld\n",
                particles, straddle, corner);
    EXPECT_EQ(particles, total);
    EXPECT_GT(straddle, particles / 4);
    EXPECT_GT(corner, particles / 20);
  }
};

/// Random particles inside the domain: cell-filling ones, anywhere, straddling a box face,
/// covering a box corner (and so three faces and edges); half-sizes from 0.05 of a cell of any
/// level up to a quarter of a level-0 cell, cubes or not.
void checkLayout(const Layout &lay, long np, std::uint64_t seed, Identities &id) {
  const Lattice3 g = latticeOf(lay);
  const Nodes tab(g);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  auto U = [&] { return uni(rng); };
  const Box3 &Dm = g.levels[0].box;
  const double h0 = g.h0(), lmax = 0.25 * h0;
  const int K = static_cast<int>(g.levels.size());
  for (long p = 0; p < np; ++p) {
    double x[3], l[3];
    bool inside = false;
    while (!inside) {
      const double lc =
          U() < 0.3 ? lmax * (0.5 + 0.5 * U())
                    : g.levels[std::min(K - 1, static_cast<int>(U() * K))].h * (0.05 + 0.95 * U());
      for (int a = 0; a < D; ++a)
        l[a] = std::min(lmax, U() < 0.5 ? lc : lc * std::exp(std::log(2.0) * (2 * U() - 1)));
      const double m = U();
      const gimp::LevelT<D> &B = g.levels[1 + static_cast<int>(U() * (K - 1)) % (K - 1)];
      if (m < 0.1) { // one of n^3 particles filling a leaf cell
        for (int a = 0; a < D; ++a)
          x[a] = Dm[a] + U() * (Dm[D + a] - Dm[a]);
        const Level3 &L = g.levels[g.leafLevelAt(x)];
        const int n = 1 + static_cast<int>(3 * U());
        const double hc = L.h / n;
        for (int a = 0; a < D; ++a) {
          x[a] = L.box[a] + (std::floor((x[a] - L.box[a]) / hc) + 0.5) * hc;
          l[a] = 0.5 * hc;
        }
      } else if (m < 0.3) {
        for (int a = 0; a < D; ++a)
          x[a] = Dm[a] + l[a] + U() * (Dm[D + a] - Dm[a] - 2 * l[a]);
      } else if (m < 0.65) { // straddling a face of a refined box
        const int ax = static_cast<int>(3 * U()) % 3, side = U() < 0.5 ? 0 : D;
        for (int a = 0; a < D; ++a)
          x[a] = a == ax ? B.box[side + a] + (2 * U() - 1) * (l[a] + 0.02 * h0)
                         : B.box[a] - 0.5 * h0 + U() * (B.box[D + a] - B.box[a] + h0);
      } else { // covering a corner of a refined box
        for (int a = 0; a < D; ++a)
          x[a] = B.box[(U() < 0.5 ? 0 : D) + a] + (2 * U() - 1) * (l[a] + 0.02 * h0);
      }
      inside = true;
      for (int a = 0; a < D; ++a)
        inside = inside && x[a] - l[a] >= Dm[a] + 1e-9 * h0 && x[a] + l[a] <= Dm[D + a] - 1e-9 * h0;
    }
    // Statistics of what was drawn.
    const int q = g.leafLevelAt(x);
    bool straddles = false;
    for (int c = 0; c < 27 && !straddles; ++c) {
      double y[3];
      for (int a = 0, cc = c; a < D; ++a, cc /= 3)
        y[a] = x[a] + 0.999 * (cc % 3 - 1) * l[a];
      straddles = g.leafLevelAt(y) != q;
    }
    id.straddle += straddles;
    for (int k = 1; k < K; ++k)
      for (int c = 0; c < 8; ++c) {
        bool in = true;
        for (int a = 0; a < D; ++a)
          in = in && std::abs(g.levels[k].box[((c >> a) & 1 ? D : 0) + a] - x[a]) < l[a];
        if (in) {
          ++id.corner;
          k = K;
          break;
        }
      }
    ++id.particles;

    const Sums s = weightSums(g, tab, x, l);
    auto where = [&] {
      return lay.name + ": " +
             at({{"x", x[0]},
                 {"y", x[1]},
                 {"z", x[2]},
                 {"lx", l[0]},
                 {"ly", l[1]},
                 {"lz", l[2]},
                 {"sum", s.w}});
    };
    id.unity.update(std::abs(s.w - 1.0), where);
    id.repro.update(std::max({std::abs(s.wr[0]), std::abs(s.wr[1]), std::abs(s.wr[2])}) / h0,
                    where);
    id.gradSum.update(std::max({std::abs(s.g[0]), std::abs(s.g[1]), std::abs(s.g[2])}) * h0, where);
    double gr = 0;
    for (int a = 0; a < D; ++a)
      for (int b = 0; b < D; ++b)
        gr = std::max(gr, std::abs(s.gr[a][b] - (a == b ? 1.0 : 0.0)));
    id.gradRepro.update(gr, where);
    id.bounds.update(std::max(-s.lo, s.hi - 1.0), where);
  }
}

void checkLayouts(const std::vector<Layout> &layouts, long total, std::uint64_t seed) {
  const long per = total / static_cast<long>(layouts.size());
  Identities id;
  for (size_t k = 0; k < layouts.size(); ++k)
    checkLayout(layouts[k], k + 1 < layouts.size() ? per : total - per * (layouts.size() - 1),
                seed++, id);
  id.report(total);
}

TEST(Lattice3D, TwoLevelIdentities) {
  checkLayouts(twoLevelLayouts(), 50000, 0x3d000001);
}

TEST(Lattice3D, ThreeLevelIdentities) {
  checkLayouts(threeLevelLayouts(), 100000, 0x3d000101);
}

// ---------------------------------------------------------------------------------------------
// 4. Bad layouts.

TEST(Lattice3D, BadLayoutsRejected) {
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
