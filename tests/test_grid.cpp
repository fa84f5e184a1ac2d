// Unit tests of the composite grid in include/gimp/grid.hpp (paper section 3): nested uniform
// levels, active nodes, influence zones [Lx-, Lx+, Ly-, Ly+] and the GIMP stencils of particles
// on the composite grid.
//
//   1. The paper's Fig. 2 grid: zones of named nodes, inactive coarse nodes, active node counts.
//   2. Every location carries exactly one active node, with zones of leaf-cell widths.
//   3. Particle weights on 2- and 3-level grids with ratios 2, 3 and 4 (boxes in the middle,
//      on the domain edge, on the parent's edge, sharing corners, coinciding): partition of
//      unity, linear reproduction and their derivatives. 3a: deeper refinement (up to 8
//      levels, total ratio up to 128, particles up to a whole level-0 cell): the valid layouts
//      are accepted and give the same identities, the invalid ones are rejected for the
//      documented reason. 3b: particles whose edge lies exactly on the domain edge.
//   4. The point shape functions (tent products with each node's zones) on the same grids.
//   5. The gradient is the derivative of the weight: central differences, node by node.
//   6. C1 continuity at transition nodes: no jump of weight or gradient along lines that cross
//      a coarse-fine interface next to hanging nodes.
//   7. Badly nested layouts are rejected with an InputError naming the option and the
//      documented reason; the layouts of tests 2-6 are all accepted.
//
// All random sampling uses a fixed-seed std::mt19937_64, so every run checks the same points.
// Random checks keep the largest error and report where (layout and particle) it occurred.
#include "gimp/grid/grid.hpp"
#include "gimp/grid/shape.hpp"

#include "test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

using gimp::test::at;
using gimp::test::Worst;

using gimp::Box;
using gimp::Grid;
using gimp::InputError;
using gimp::Level;
using gimp::LevelSpec;
using gimp::Scene;
using Stencils = gimp::Stencils<gimp::kDim>;
using gimp::shape::tent;

// ---------------------------------------------------------------------------------------------
// Layouts.

/// A refined box: corners in level-0 cells from the domain origin (fractions where they fall on
/// the parent's grid lines) and the refinement ratio to its parent.
struct BoxSpec {
  double i0, j0, i1, j1;
  int ratio;
};

struct Layout {
  std::string name;
  int nx, ny; // level-0 cells of the domain
  std::vector<BoxSpec> boxes;
};

// Domain origin and level-0 cell size that are not binary fractions, so that node coordinates
// carry round-off as in real scenes.
constexpr double kX0 = -1.3, kY0 = 0.7, kH0 = 0.37;

Scene sceneOf(const Layout &lay, double x0 = kX0, double y0 = kY0, double h0 = kH0) {
  Scene sc;
  sc.h = h0;
  sc.domain = {x0, y0, x0 + lay.nx * h0, y0 + lay.ny * h0};
  sc.levels.assign(1, LevelSpec{sc.domain, 1});
  for (const BoxSpec &b : lay.boxes)
    sc.levels.push_back(
        LevelSpec{{x0 + b.i0 * h0, y0 + b.j0 * h0, x0 + b.i1 * h0, y0 + b.j1 * h0}, b.ratio});
  return sc;
}

/// A grid from a scene given in code (plain numbers, not options).
Scene plainScene(const Box &domain, double h, const std::vector<LevelSpec> &fine) {
  Scene sc;
  sc.h = h;
  sc.domain = domain;
  sc.levels.assign(1, LevelSpec{domain, 1});
  sc.levels.insert(sc.levels.end(), fine.begin(), fine.end());
  return sc;
}

std::unique_ptr<Grid> makeGrid(const Scene &sc) {
  auto g = std::make_unique<Grid>();
  EXPECT_EQ(static_cast<int>(g->create(PETSC_COMM_SELF, sc)), 0);
  return g;
}

/// 2-level layouts: one fine box in the middle, on the domain edge, in a domain corner, over one
/// level-0 cell and over the whole domain; ratios 2, 3 and 4.
std::vector<Layout> twoLevelLayouts() {
  std::vector<Layout> v;
  for (int r : {2, 3, 4}) {
    const std::string s = " r=" + std::to_string(r);
    v.push_back({"middle" + s, 10, 8, {{3, 2, 7, 6, r}}});
    v.push_back({"domain edge" + s, 10, 8, {{0, 3, 4, 8, r}}});
    v.push_back({"domain corner" + s, 10, 8, {{6, 0, 10, 3, r}}});
    v.push_back({"one cell" + s, 10, 8, {{5, 4, 6, 5, r}}});
    v.push_back({"whole domain" + s, 10, 8, {{0, 0, 10, 8, r}}});
  }
  return v;
}

/// 3-level layouts (level-2 box in level-1 cells f = 1 / r1 of a level-0 cell): in the middle of
/// level 1, on level 1's left edge, in level 1's upper-right corner, along the domain edge with
/// all three levels sharing the corner (0, 8), a one-cell strip across level 1 from its bottom to
/// its top edge, and coinciding with level 1 (a level-2 box next to level-0 cells).
std::vector<Layout> threeLevelLayouts() {
  std::vector<Layout> v;
  const std::pair<int, int> ratios[] = {{2, 2}, {3, 3}, {4, 4}, {2, 4}, {4, 3}, {3, 2}};
  for (const auto &[r1, r2] : ratios) {
    const double f = 1.0 / r1;
    const std::string s = " r=" + std::to_string(r1) + "," + std::to_string(r2);
    v.push_back({"middle" + s, 10, 8, {{2, 2, 8, 6, r1}, {3 + f, 3, 6, 5 - f, r2}}});
    v.push_back({"parent edge" + s, 10, 8, {{2, 2, 8, 6, r1}, {2, 3, 4 + f, 5, r2}}});
    v.push_back({"parent corner" + s, 10, 8, {{2, 2, 8, 6, r1}, {6 - f, 4, 8, 6, r2}}});
    v.push_back({"domain edge" + s, 10, 8, {{0, 0, 5, 8, r1}, {0, 2, 3, 8, r2}}});
    v.push_back({"strip" + s, 10, 8, {{2, 2, 8, 6, r1}, {4, 2, 4 + f, 6, r2}}});
    v.push_back({"coincident" + s, 10, 8, {{3, 2, 7, 6, r1}, {3, 2, 7, 6, r2}}});
  }
  return v;
}

/// Level of window node n.
int levelOf(const Grid &g, PetscInt n) {
  int k = 0;
  while (k + 1 < static_cast<int>(g.levels.size()) && n >= g.levels[k + 1].offset)
    ++k;
  return k;
}

/// Window index of level k's node (i, j).
PetscInt windowIndex(const Grid &g, int k, PetscInt i, PetscInt j) {
  const Level &L = g.levels[k];
  return L.offset + (j - L.wj0) * L.wnx() + (i - L.wi0);
}

/// Active window nodes at (x, y).
std::vector<PetscInt> activeAt(const Grid &g, double x, double y) {
  std::vector<PetscInt> v;
  const double tol = 1e-9 * g.hMin();
  for (PetscInt n = 0; n < g.nWindow; ++n)
    if (g.active[n] && std::abs(g.X[n] - x) < tol && std::abs(g.Y[n] - y) < tol) v.push_back(n);
  return v;
}

/// The particle lies inside the domain, clear of its edges by at least 1e-9 h0. (A particle whose
/// edge lies exactly on the domain edge is test 3b.)
bool insideDomain(const Grid &g, double x, double y, double lx, double ly) {
  const Box &D = g.levels[0].box;
  const double m = 1e-9 * g.h0();
  return x - lx >= D[0] + m && x + lx <= D[2] - m && y - ly >= D[1] + m && y + ly <= D[3] - m;
}

/// Random particles that exercise the composite grid: cell-filling particles (edges on grid
/// lines), particles anywhere, straddling box edges, covering box corners and around transition
/// nodes; half-sizes from 0.05 of a cell of any level up to half a level-0 cell (a coarse
/// particle that moved into a fine region; up to a whole one on request), square or not. Every
/// particle lies in the domain.
class Sampler {
public:
  Sampler(const Grid &g, std::uint64_t seed) : g_(g), rng_(seed) {
    for (size_t k = 1; k < g.levels.size(); ++k) {
      const Box &b = g.levels[k].box;
      edges_.push_back({0, b[0], b[1], b[3]});
      edges_.push_back({0, b[2], b[1], b[3]});
      edges_.push_back({1, b[1], b[0], b[2]});
      edges_.push_back({1, b[3], b[0], b[2]});
      for (double x : {b[0], b[2]})
        for (double y : {b[1], b[3]})
          corners_.push_back({x, y});
    }
    for (PetscInt n = 0; n < g.nWindow; ++n)
      if (g.active[n] && !g.regular[n]) transition_.push_back(n);
  }

  double U() { return uni_(rng_); }
  template <class T> const T &pick(const std::vector<T> &v) {
    return v[std::min(v.size() - 1, static_cast<size_t>(U() * v.size()))];
  }

  /// A particle; half-sizes up to lmax (default: half a level-0 cell).
  void draw(double &x, double &y, double &lx, double &ly, bool cellFilling = true,
            double lmax = 0.0) {
    const Box &D = g_.levels[0].box;
    const double h0 = g_.h0();
    if (lmax <= 0.0) lmax = 0.5 * h0;
    const int K = static_cast<int>(g_.levels.size());
    do {
      if (U() < 0.3) {
        lx = lmax * (0.5 + 0.5 * U());
      } else {
        const Level &L = g_.levels[std::min(K - 1, static_cast<int>(U() * K))];
        lx = L.h * (0.05 + 0.95 * U());
      }
      ly = U() < 0.5 ? lx : lx * std::exp(std::log(2.0) * (2.0 * U() - 1.0));
      lx = std::min(lx, lmax);
      ly = std::min(ly, lmax);
      const double m = U();
      if (m < (cellFilling ? 0.1 : 0.0)) {
        // One of n x n particles filling a leaf cell.
        x = D[0] + U() * (D[2] - D[0]);
        y = D[1] + U() * (D[3] - D[1]);
        const Level &L = g_.levels[g_.leafLevelAt(x, y)];
        const int n = 1 + static_cast<int>(3 * U());
        const double hc = L.h / n;
        x = L.box[0] + (std::floor((x - L.box[0]) / hc) + 0.5) * hc;
        y = L.box[1] + (std::floor((y - L.box[1]) / hc) + 0.5) * hc;
        lx = ly = 0.5 * hc;
      } else if (m < 0.3 || edges_.empty()) {
        x = D[0] + lx + U() * (D[2] - D[0] - 2 * lx);
        y = D[1] + ly + U() * (D[3] - D[1] - 2 * ly);
      } else if (m < 0.55) { // straddling a box edge
        const auto &e = pick(edges_);
        const double along = e[2] - 0.5 * h0 + U() * (e[3] - e[2] + h0);
        if (e[0] == 0) {
          x = e[1] + (2 * U() - 1) * (lx + 0.02 * h0);
          y = along;
        } else {
          x = along;
          y = e[1] + (2 * U() - 1) * (ly + 0.02 * h0);
        }
      } else if (m < 0.75) { // covering a box corner
        const auto &c = pick(corners_);
        x = c[0] + (2 * U() - 1) * (lx + 0.02 * h0);
        y = c[1] + (2 * U() - 1) * (ly + 0.02 * h0);
      } else { // around a transition node
        const PetscInt n = pick(transition_);
        const double *z = &g_.zone[4 * n];
        x = g_.X[n] + (2 * U() - 1) * (lx + std::max(z[0], z[1]));
        y = g_.Y[n] + (2 * U() - 1) * (ly + std::max(z[2], z[3]));
      }
    } while (!insideDomain(g_, x, y, lx, ly));
  }

  /// The particle covers points of leaf cells of two levels.
  bool straddles(double x, double y, double lx, double ly) const {
    const int q = g_.leafLevelAt(x, y);
    for (double sx : {-0.999, 0.0, 0.999})
      for (double sy : {-0.999, 0.0, 0.999})
        if (g_.leafLevelAt(x + sx * lx, y + sy * ly) != q) return true;
    return false;
  }
  /// A box corner lies strictly inside the particle.
  bool coversCorner(double x, double y, double lx, double ly) const {
    for (const auto &c : corners_)
      if (std::abs(c[0] - x) < lx && std::abs(c[1] - y) < ly) return true;
    return false;
  }

private:
  const Grid &g_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> uni_{0.0, 1.0};
  std::vector<std::array<double, 4>> edges_; // axis (0: line x = c), c, from, to
  std::vector<std::array<double, 2>> corners_;
  std::vector<PetscInt> transition_; // active nodes with a zone other than their level's h
};

// ---------------------------------------------------------------------------------------------
// 1. The paper's Fig. 2: coarse grid (0,0)-(8,6) with h = 2, fine box (2,2)-(6,6), ratio 2.

/// The single active node at (x, y) has level k and zones z (checked in the window data and by
/// the pure-geometry zonesOf).
void expectNode(const Grid &g, double x, double y, int k, std::array<double, 4> z) {
  const std::vector<PetscInt> n = activeAt(g, x, y);
  ASSERT_EQ(n.size(), 1u) << "active nodes at (" << x << ", " << y << ")";
  EXPECT_EQ(levelOf(g, n[0]), k) << "(" << x << ", " << y << ")";
  const Level &L = g.levels[k];
  const auto i = static_cast<PetscInt>(std::llround((x - L.box[0]) / L.h));
  const auto j = static_cast<PetscInt>(std::llround((y - L.box[1]) / L.h));
  EXPECT_TRUE(g.nodeActive(k, i, j));
  double zg[4];
  g.zonesOf(k, i, j, zg);
  for (int s = 0; s < 4; ++s) {
    EXPECT_EQ(g.zone[4 * n[0] + s], z[s]) << "(" << x << ", " << y << ") zone " << s;
    EXPECT_EQ(zg[s], z[s]) << "(" << x << ", " << y << ") zonesOf " << s;
  }
  EXPECT_EQ(g.regular[n[0]] != 0, z[0] == L.h && z[1] == L.h && z[2] == L.h && z[3] == L.h);
}

TEST(GridFig2, PaperZones) {
  const auto g = makeGrid(plainScene({0, 0, 8, 6}, 2.0, {{{2, 2, 6, 6}, 2}}));
  ASSERT_EQ(g->levels.size(), 2u);
  EXPECT_EQ(g->levels[1].h, 1.0);
  // The transition nodes named in the paper.
  expectNode(*g, 2, 3, 1, {2, 1, 1, 1});
  expectNode(*g, 2, 4, 1, {2, 1, 1, 1});
  expectNode(*g, 2, 2, 1, {2, 1, 2, 1});
  // More nodes of the same figure: hanging nodes on the bottom and right edges, fine nodes on
  // the domain's top edge, an interior fine node and coarse corners.
  expectNode(*g, 3, 2, 1, {1, 1, 2, 1});
  expectNode(*g, 6, 3, 1, {1, 2, 1, 1});
  expectNode(*g, 6, 2, 1, {1, 2, 2, 1});
  expectNode(*g, 4, 6, 1, {1, 1, 1, 0});
  expectNode(*g, 6, 6, 1, {1, 2, 1, 0});
  expectNode(*g, 2, 6, 1, {2, 1, 1, 0});
  expectNode(*g, 4, 5, 1, {1, 1, 1, 1});
  expectNode(*g, 0, 0, 0, {0, 2, 0, 2});
  expectNode(*g, 8, 6, 0, {2, 0, 2, 0});
  expectNode(*g, 0, 4, 0, {0, 2, 2, 2});
  expectNode(*g, 4, 0, 0, {2, 2, 0, 2});

  // Coarse nodes in the closed fine box are inactive (nodes on its boundary belong to the fine
  // level); the others are active.
  for (PetscInt j = 0; j < 4; ++j)
    for (PetscInt i = 0; i < 5; ++i) {
      const bool covered = i >= 1 && i <= 3 && j >= 1;
      EXPECT_EQ(g->nodeActive(0, i, j), !covered) << "coarse node " << i << "," << j;
      EXPECT_EQ(g->active[windowIndex(*g, 0, i, j)] != 0, !covered);
    }
  EXPECT_EQ(g->activeNodes(0), 20 - 9);
  EXPECT_EQ(g->activeNodes(1), 25);
  EXPECT_EQ(g->nWindow, 20 + 25);
  EXPECT_EQ(std::count(g->active.begin(), g->active.end(), 1), 36);
}

TEST(GridFig2, EnlargedDomain) {
  // The same fine box inside a larger domain: the box is surrounded by coarse cells.
  const auto g = makeGrid(plainScene({0, 0, 12, 8}, 2.0, {{{2, 2, 6, 6}, 2}}));
  expectNode(*g, 10, 4, 0, {2, 2, 2, 2}); // away from the fine box
  expectNode(*g, 8, 6, 0, {2, 2, 2, 2});  // diagonal to the box corner (6, 6)
  expectNode(*g, 6, 8, 0, {2, 2, 2, 0});
  expectNode(*g, 2, 3, 1, {2, 1, 1, 1});
  expectNode(*g, 2, 4, 1, {2, 1, 1, 1});
  expectNode(*g, 2, 2, 1, {2, 1, 2, 1});
  expectNode(*g, 6, 6, 1, {1, 2, 1, 2});
  expectNode(*g, 2, 6, 1, {2, 1, 1, 2});
  expectNode(*g, 5, 6, 1, {1, 1, 1, 2});
  expectNode(*g, 4, 6, 1, {1, 1, 1, 2});
  expectNode(*g, 4, 4, 1, {1, 1, 1, 1});
  for (PetscInt j = 0; j < 5; ++j)
    for (PetscInt i = 0; i < 7; ++i) {
      const bool covered = i >= 1 && i <= 3 && j >= 1 && j <= 3;
      EXPECT_EQ(g->nodeActive(0, i, j), !covered) << "coarse node " << i << "," << j;
    }
  EXPECT_EQ(g->activeNodes(0), 35 - 9);
  EXPECT_EQ(g->activeNodes(1), 25);
  EXPECT_EQ(std::count(g->active.begin(), g->active.end(), 1), 51);
}

TEST(GridFig2, SingleLevelZones) {
  // The paper: the node (2, 2) has zone [2, 2, 2, 2] in the coarse grid alone and [0, 1, 0, 1]
  // in the fine grid alone (a uniform grid is the one-level case).
  const auto coarse = makeGrid(plainScene({0, 0, 8, 6}, 2.0, {}));
  expectNode(*coarse, 2, 2, 0, {2, 2, 2, 2});
  EXPECT_EQ(coarse->activeNodes(0), 20);
  const auto fine = makeGrid(plainScene({2, 2, 6, 6}, 1.0, {}));
  expectNode(*fine, 2, 2, 0, {0, 1, 0, 1});
  expectNode(*fine, 4, 4, 0, {1, 1, 1, 1});
  EXPECT_EQ(fine->activeNodes(0), 25);
}

// ---------------------------------------------------------------------------------------------
// 2. Node structure of every layout: one active node per location, zones of leaf-cell widths.

TEST(GridNodes, OneActiveNodePerLocation) {
  std::vector<Layout> layouts = twoLevelLayouts();
  for (const Layout &l : threeLevelLayouts())
    layouts.push_back(l);
  for (const Layout &lay : layouts) {
    SCOPED_TRACE(lay.name);
    const auto g = makeGrid(sceneOf(lay));
    const int K = static_cast<int>(g->levels.size());
    const Box &D = g->levels[0].box;
    // Finest-lattice coordinates of every node, and the active copies there.
    std::map<std::pair<std::int64_t, std::int64_t>, int> activeCount;
    std::int64_t activeTotal = 0;
    std::set<double> widths;
    for (const Level &L : g->levels)
      widths.insert(L.h);
    for (int k = 0; k < K; ++k) {
      const Level &L = g->levels[k];
      ASSERT_EQ(L.wnx() * (L.wj1 - L.wj0), L.M * L.N); // one rank: the window is everything
      for (PetscInt j = 0; j < L.N; ++j)
        for (PetscInt i = 0; i < L.M; ++i) {
          const PetscInt n = windowIndex(*g, k, i, j);
          const auto key = std::make_pair(L.u0 + i * L.step, L.v0 + j * L.step);
          activeCount[key] += g->active[n];
          EXPECT_EQ(g->active[n] != 0, g->nodeActive(k, i, j));
          if (!g->active[n]) {
            // An inactive node lies in the closed box of a finer level.
            bool covered = false;
            for (int q = k + 1; q < K; ++q) {
              const Level &F = g->levels[q];
              covered = covered || (key.first >= F.u0 && key.first <= F.u1 && key.second >= F.v0 &&
                                    key.second <= F.v1);
            }
            EXPECT_TRUE(covered) << "level " << k << " node " << i << "," << j;
            continue;
          }
          ++activeTotal;
          // Zones: a leaf-cell width of some level inside the domain, zero outside it.
          const double *z = &g->zone[4 * n];
          const int side[4] = {0, 2, 1, 3}; // domain coordinate bounding each side
          for (int s = 0; s < 4; ++s) {
            const double c = s < 2 ? g->X[n] : g->Y[n];
            if (std::abs(c - D[side[s]]) < 1e-12 * g->h0())
              EXPECT_EQ(z[s], 0.0) << "level " << k << " node " << i << "," << j << " side " << s;
            else
              EXPECT_EQ(widths.count(z[s]), 1u) << "level " << k << " node " << i << "," << j
                                                << " side " << s << " zone " << z[s];
          }
        }
    }
    for (const auto &[key, c] : activeCount)
      EXPECT_EQ(c, 1) << "lattice point " << key.first << "," << key.second;
    std::int64_t byLevel = 0;
    for (int k = 0; k < K; ++k)
      byLevel += g->activeNodes(k);
    EXPECT_EQ(byLevel, activeTotal);
  }
}

// ---------------------------------------------------------------------------------------------
// 3. Particle weights on the composite grid.

struct Identities {
  Worst unity, reproX, reproY, gradSum, gradRepro, bounds, nodes;
  long particles = 0, straddle = 0, corner = 0, bigInFine = 0;

  void report(long total) {
    EXPECT_WORST_LE(unity, 1e-12);
    EXPECT_WORST_LE(reproX, 1e-12);
    EXPECT_WORST_LE(reproY, 1e-12);
    EXPECT_WORST_LE(gradSum, 1e-10);
    EXPECT_WORST_LE(gradRepro, 1e-10);
    EXPECT_WORST_LE(bounds, 0.0);
    EXPECT_WORST_LE(nodes, 0.0);
    std::printf("  particles %ld: straddling two levels %ld, covering a box corner %ld, "
                "half-size >= h0/4 in a fine level %ld\n",
                particles, straddle, corner, bigInFine);
    EXPECT_EQ(particles, total);
    EXPECT_GT(straddle, particles / 4);
    EXPECT_GT(corner, particles / 10);
    EXPECT_GT(bigInFine, particles / 20);
  }
};

void checkLayout(const Layout &lay, long np, std::uint64_t seed, Identities &id,
                 double lmax = 0.0) {
  const auto gp = makeGrid(sceneOf(lay));
  const Grid &g = *gp;
  const double h0 = g.h0();
  Sampler sample(g, seed);
  std::vector<double> x(2 * np), l(2 * np);
  for (long p = 0; p < np; ++p) {
    sample.draw(x[2 * p], x[2 * p + 1], l[2 * p], l[2 * p + 1], true, lmax);
    const double xp = x[2 * p], yp = x[2 * p + 1], lx = l[2 * p], ly = l[2 * p + 1];
    id.straddle += sample.straddles(xp, yp, lx, ly);
    id.corner += sample.coversCorner(xp, yp, lx, ly);
    id.bigInFine += std::max(lx, ly) >= 0.25 * h0 && g.leafLevelAt(xp, yp) > 0;
  }
  id.particles += np;
  Stencils s;
  g.buildStencils(static_cast<PetscInt>(np), x.data(), l.data(), s);
  ASSERT_EQ(s.start.size(), static_cast<size_t>(np) + 1);
  std::vector<long> seen(g.nWindow, -1);
  for (long p = 0; p < np; ++p) {
    const double xp = x[2 * p], yp = x[2 * p + 1];
    double sw = 0, swx = 0, swy = 0, sgx = 0, sgy = 0;
    double mxx = 0, mxy = 0, myx = 0, myy = 0, lo = 0, hi = 0;
    int badNode = 0;
    for (PetscInt e = s.start[p]; e < s.start[p + 1]; ++e) {
      const PetscInt n = s.node[e];
      if (n < 0 || n >= g.nWindow || !g.active[n] || seen[n] == p) {
        badNode = 1; // outside the window, inactive or listed twice
        continue;
      }
      seen[n] = p;
      const double w = s.w[0][e] * s.w[1][e], dx = s.g[0][e] * s.w[1][e],
                   dy = s.w[0][e] * s.g[1][e];
      const double rx = g.X[n] - xp, ry = g.Y[n] - yp;
      sw += w;
      // Linear reproduction sum_i w_i x_i = x_p as sum_i w_i (x_i - x_p) = 0 (the same given
      // the partition of unity), free of the cancellation of large coordinates.
      swx += w * rx;
      swy += w * ry;
      sgx += dx;
      sgy += dy;
      // Its derivative: sum_i grad w_i (x_i - x_p)^T = identity.
      mxx += dx * rx;
      mxy += dx * ry;
      myx += dy * rx;
      myy += dy * ry;
      lo = std::min(lo, w);
      hi = std::max(hi, w);
    }
    auto where = [&] {
      return lay.name + ": " +
             at({{"xp", xp}, {"yp", yp}, {"lx", l[2 * p]}, {"ly", l[2 * p + 1]}, {"sum", sw}});
    };
    id.unity.update(std::abs(sw - 1.0), where);
    id.reproX.update(std::abs(swx) / h0, where);
    id.reproY.update(std::abs(swy) / h0, where);
    id.gradSum.update(std::max(std::abs(sgx), std::abs(sgy)) * h0, where);
    id.gradRepro.update(
        std::max({std::abs(mxx - 1.0), std::abs(myy - 1.0), std::abs(mxy), std::abs(myx)}), where);
    id.bounds.update(std::max(-lo, hi - 1.0), where);
    id.nodes.update(badNode, where);
  }
}

// 1e5 particles over the 15 two-level layouts.
TEST(GridStencils, TwoLevelIdentities) {
  const std::vector<Layout> layouts = twoLevelLayouts();
  const long total = 100000, per = total / static_cast<long>(layouts.size());
  Identities id;
  std::uint64_t seed = 0x6a1d0001;
  for (size_t k = 0; k < layouts.size(); ++k)
    checkLayout(layouts[k], k + 1 < layouts.size() ? per : total - per * (layouts.size() - 1),
                seed++, id);
  id.report(total);
}

// 1e5 particles over the 36 three-level layouts.
TEST(GridStencils, ThreeLevelIdentities) {
  const std::vector<Layout> layouts = threeLevelLayouts();
  const long total = 100000, per = total / static_cast<long>(layouts.size());
  Identities id;
  std::uint64_t seed = 0x6a1d1001;
  for (size_t k = 0; k < layouts.size(); ++k)
    checkLayout(layouts[k], k + 1 < layouts.size() ? per : total - per * (layouts.size() - 1),
                seed++, id);
  id.report(total);
}

// 3a. Deeper refinement: up to the scene's 8 levels, ratios up to its maximum 16, total ratios
// up to 128, and particles up to a whole level-0 cell (half-size h0, the largest a run allows).
// Every layout is classified in advance. A layout whose corners lie on its parent's grid lines
// (to the relative tolerance 1e-9 of setGeometry, docs/options.md), with a non-empty box inside
// its parent, is valid (docs/method.md, "Levels"): it must be accepted and give the identities
// of test 3 with the same tolerances and sampling coverage. Any other layout must be rejected
// with a one-line InputError that names the offending level's option and gives the documented
// reason. (The ratio range 2..16 and the level count 1..8 are the scene parser's checks, not
// setGeometry's.) An earlier version skipped every rejected layout, so a setGeometry that
// rejected everything passed.

// The documented reasons for rejecting a layout, as setGeometry words them.
const char *const kOffLines = "is not on a grid line of level";
const char *const kNotInside = "(levels must be nested)";
const char *const kEmpty = "needs x1 > x0 and y1 > y0";

struct DeepCase {
  Layout lay;
  const char *option; // nullptr: valid; otherwise the option the message must name
  const char *reason; // the documented reason the message must give
  const char *why;    // why the layout is valid or must be rejected
};

std::vector<DeepCase> deepCases() {
  // 8 levels of ratio 2 (total 128), boxes nested down to a quarter of a level-0 cell.
  const std::vector<BoxSpec> eight = {{1, 1, 9, 7, 2},
                                      {2, 2, 8, 6, 2},
                                      {3, 2, 7, 6, 2},
                                      {4, 3, 6, 5, 2},
                                      {4.5, 3.5, 5.5, 4.5, 2},
                                      {4.75, 3.75, 5.25, 4.25, 2},
                                      {4.875, 3.875, 5.125, 4.125, 2}};
  std::vector<BoxSpec> eightEmpty = eight;
  eightEmpty.back() = {4.875, 3.875, 4.875, 4.125, 2};
  return {
      // Valid.
      {{"r=16", 10, 8, {{3, 2, 7, 6, 16}}}, nullptr, nullptr, "the largest ratio"},
      {{"r=4,4", 10, 8, {{2, 2, 8, 6, 4}, {4, 3, 6, 5, 4}}}, nullptr, nullptr, "total ratio 16"},
      {{"r=2,16", 10, 8, {{2, 2, 8, 6, 2}, {4, 3, 6, 5, 16}}},
       nullptr,
       nullptr,
       "total ratio 32, ratio 16 inside ratio 2"},
      {{"r=4,8", 10, 8, {{2, 2, 8, 6, 4}, {4, 3, 6, 5, 8}}}, nullptr, nullptr, "total ratio 32"},
      {{"r=5,5", 10, 8, {{2, 2, 8, 6, 5}, {4, 3, 6, 5, 5}}},
       nullptr,
       nullptr,
       "lattice unit h0/25, not a binary fraction"},
      {{"r=2,2,2,4", 10, 8, {{1, 1, 9, 7, 2}, {2, 2, 8, 6, 2}, {3, 2, 7, 6, 2}, {4, 3, 6, 5, 4}}},
       nullptr,
       nullptr,
       "5 levels, level 3 on level 2's bottom and top edges"},
      {{"8 levels r=2", 10, 8, eight}, nullptr, nullptr, "the scene's 8 levels, total ratio 128"},
      // A corner off its line by round-off (1e-15 cells, 8 ulp of the coordinate, as a decimal
      // option may carry), and one 1e-12 cells off, accepted within the 1e-9 tolerance: the
      // level's box is put on the lattice, so its weights keep the partition of unity to 1e-12
      // (with the box used as given they missed it by 3e-11).
      {{"r=4,8 corner 1e-15 off", 10, 8, {{2, 2, 8, 6, 4}, {4 + 1e-15, 3, 6, 5, 8}}},
       nullptr,
       nullptr,
       "corner off a level-1 line by round-off, well within the 1e-9 tolerance"},
      {{"r=4,8 corner 1e-12 off", 10, 8, {{2, 2, 8, 6, 4}, {4 + 1e-12, 3, 6, 5, 8}}},
       nullptr,
       nullptr,
       "corner 1e-12 cells off a level-1 line, within the 1e-9 tolerance"},
      // Rejected.
      {{"r=16 corner on its own lines", 10, 8, {{3.0625, 2, 7, 6, 16}}},
       "-gimp_level1_box",
       kOffLines,
       "x0 = 3 + 1/16 cells: on a level-1 line, not on a level-0 line"},
      {{"r=4,8 corner on its own lines", 10, 8, {{2, 2, 8, 6, 4}, {4.125, 3, 6, 5, 8}}},
       "-gimp_level2_box",
       kOffLines,
       "x0 = 4 + 1/8 cells: on a level-2 line, not on a level-1 one"},
      {{"r=5,5 corner 1e-6 off", 10, 8, {{2, 2, 8, 6, 5}, {4 + 1e-6, 3, 6, 5, 5}}},
       "-gimp_level2_box",
       kOffLines,
       "x0 5e-6 level-1 cells off a line, beyond the 1e-9 tolerance"},
      {{"r=2,2,2,4 level 4 beyond level 3",
        10,
        8,
        {{1, 1, 9, 7, 2}, {2, 2, 8, 6, 2}, {3, 2, 7, 6, 2}, {2, 3, 6, 5, 4}}},
       "-gimp_level4_box",
       kNotInside,
       "level 4 starts at x = 2, level 3 at x = 3"},
      {{"r=4,4 level 2 across level 1's corner", 10, 8, {{2, 2, 8, 6, 4}, {7, 5, 9, 7, 4}}},
       "-gimp_level2_box",
       kNotInside,
       "level 2 reaches (9, 7), level 1 ends at (8, 6)"},
      {{"8 levels, empty level 7", 10, 8, eightEmpty},
       "-gimp_level7_box",
       kEmpty,
       "level 7 has zero width"},
  };
}

TEST(GridStencils, DeepRefinementLayouts) {
  const std::vector<DeepCase> cases = deepCases();
  int validExpected = 0, accepted = 0, rejected = 0;
  std::uint64_t seed = 0x6a1d5001;
  for (const DeepCase &c : cases) {
    SCOPED_TRACE(c.lay.name + " (" + c.why + ")");
    const bool valid = c.reason == nullptr;
    validExpected += valid;
    std::string msg;
    bool threw = false;
    {
      Grid probe;
      try {
        probe.setGeometry(sceneOf(c.lay));
      } catch (const InputError &e) {
        threw = true;
        msg = e.what();
      }
    }
    if (!valid) {
      EXPECT_TRUE(threw) << c.lay.name << ": accepted, must be rejected: " << c.why;
      if (!threw) continue;
      ++rejected;
      std::printf("  %-38s rejected: %s\n", c.lay.name.c_str(), msg.c_str());
      EXPECT_NE(msg.find("option " + std::string(c.option) + " "), std::string::npos)
          << "message does not name " << c.option;
      EXPECT_NE(msg.find(c.reason), std::string::npos) << "message does not say " << c.reason;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line";
      continue;
    }
    EXPECT_FALSE(threw) << c.lay.name << ": rejected, must be accepted (" << c.why << "): " << msg;
    if (threw) continue;
    ++accepted;
    std::printf("  %-38s accepted, %zu levels\n", c.lay.name.c_str(), c.lay.boxes.size() + 1);
    Identities id;
    const long np = 4000;
    checkLayout(c.lay, np, seed++, id, kH0);
    id.report(np);
  }
  // 8 valid and 6 invalid layouts: the counts also guard the list (turning a case from valid to
  // rejected, or back, must be a deliberate edit of these numbers).
  EXPECT_EQ(validExpected, 9);
  EXPECT_EQ(static_cast<int>(cases.size()) - validExpected, 6);
  EXPECT_EQ(accepted, validExpected);
  EXPECT_EQ(rejected, static_cast<int>(cases.size()) - validExpected);
}

// 3b. Particles whose edge lies on the domain edge, as seeding makes them for a body that ends on
// the domain edge (a body box may equal the domain): n x n particles in every leaf cell along the
// domain edge, positions as the seeding computes them. The weights sum to 1 and the gradients to
// 0 as inside; the edge node's tent must be read as 1 where the particle's edge meets the domain
// edge, even when x_p - l - x_0 rounds to a negative ~1e-17.
TEST(GridStencils, ParticleTouchingDomainEdge) {
  Worst unity, repro, gradSum, gradRepro;
  long offGrad = 0, total = 0;
  for (double x0 : {0.1, 0.7, -1.3})
    for (double h0 : {0.1, 0.3, 0.37})
      for (const Layout &lay :
           {Layout{"uniform", 6, 5, {}}, Layout{"domain edge r=2", 6, 5, {{0, 2, 3, 5, 2}}}}) {
        const auto gp = makeGrid(sceneOf(lay, x0, x0, h0));
        const Grid &g = *gp;
        const Box &D = g.levels[0].box;
        std::vector<double> x, l;
        for (int n : {1, 2, 3})
          for (size_t q = 0; q < g.levels.size(); ++q) {
            const Level &L = g.levels[q];
            const double d = L.h / n;
            for (PetscInt j = 0; j + 1 < L.N; ++j)
              for (PetscInt i = 0; i + 1 < L.M; ++i) {
                const double cx0 = L.box[0] + i * L.h, cy0 = L.box[1] + j * L.h;
                if (g.leafLevelAt(cx0 + 0.5 * L.h, cy0 + 0.5 * L.h) != static_cast<int>(q))
                  continue;
                for (int b = 0; b < n; ++b)
                  for (int a = 0; a < n; ++a) {
                    const bool edge = (i == 0 && a == 0 && cx0 == D[0]) ||
                                      (j == 0 && b == 0 && cy0 == D[1]) ||
                                      (i + 2 == L.M && a + 1 == n && L.box[2] == D[2]) ||
                                      (j + 2 == L.N && b + 1 == n && L.box[3] == D[3]);
                    if (!edge) continue;
                    x.push_back(cx0 + (a + 0.5) * d);
                    x.push_back(cy0 + (b + 0.5) * d);
                    l.push_back(0.5 * d);
                    l.push_back(0.5 * d);
                  }
              }
          }
        const auto np = static_cast<PetscInt>(l.size() / 2);
        Stencils s;
        g.buildStencils(np, x.data(), l.data(), s);
        for (PetscInt p = 0; p < np; ++p) {
          const double xp = x[2 * p], yp = x[2 * p + 1];
          double sw = 0, swx = 0, swy = 0, sgx = 0, sgy = 0, mxx = 0, mxy = 0, myx = 0, myy = 0;
          for (PetscInt e = s.start[p]; e < s.start[p + 1]; ++e) {
            const PetscInt n = s.node[e];
            const double w = s.w[0][e] * s.w[1][e], dx = s.g[0][e] * s.w[1][e],
                         dy = s.w[0][e] * s.g[1][e];
            const double rx = g.X[n] - xp, ry = g.Y[n] - yp;
            sw += w;
            swx += w * rx;
            swy += w * ry;
            sgx += dx;
            sgy += dy;
            mxx += dx * rx;
            mxy += dx * ry;
            myx += dy * rx;
            myy += dy * ry;
          }
          auto where = [&] {
            return lay.name + ": " +
                   at({{"x0 = y0", x0},
                       {"h0", h0},
                       {"xp", xp},
                       {"yp", yp},
                       {"l", l[2 * p]},
                       {"xp - l - x0", xp - l[2 * p] - D[0]},
                       {"yp - l - y0", yp - l[2 * p + 1] - D[1]},
                       {"sum gx", sgx},
                       {"sum gy", sgy}});
          };
          ++total;
          offGrad += std::max(std::abs(sgx), std::abs(sgy)) * h0 > 1e-10;
          unity.update(std::abs(sw - 1.0), where);
          repro.update(std::max(std::abs(swx), std::abs(swy)) / h0, where);
          gradSum.update(std::max(std::abs(sgx), std::abs(sgy)) * h0, where);
          gradRepro.update(
              std::max({std::abs(mxx - 1.0), std::abs(myy - 1.0), std::abs(mxy), std::abs(myx)}),
              where);
        }
      }
  EXPECT_WORST_LE(unity, 1e-12);
  EXPECT_WORST_LE(repro, 1e-12);
  EXPECT_WORST_LE(gradSum, 1e-10);
  EXPECT_WORST_LE(gradRepro, 1e-10);
  std::printf("  gradients not summing to 0: %ld of %ld edge particles\n", offGrad, total);
}

// ---------------------------------------------------------------------------------------------
// 4. Point shape functions: S_i(x, y) = tent(x - X_i; Lx-, Lx+) tent(y - Y_i; Ly-, Ly+) summed
// over all active nodes of the composite grid.

TEST(GridPointShape, PartitionOfUnityAndLinearReproduction) {
  std::vector<Layout> layouts = twoLevelLayouts();
  for (const Layout &l : threeLevelLayouts())
    layouts.push_back(l);
  layouts.push_back({"fig2", 4, 3, {{1, 1, 3, 3, 2}}});
  Worst unity, reproX, reproY, bounds;
  std::uint64_t seed = 0x6a1d2001;
  for (const Layout &lay : layouts) {
    const auto gp = makeGrid(sceneOf(lay));
    const Grid &g = *gp;
    const double h0 = g.h0();
    const Box &D = g.levels[0].box;
    Sampler sample(g, seed++);
    std::vector<PetscInt> act;
    for (PetscInt n = 0; n < g.nWindow; ++n)
      if (g.active[n]) act.push_back(n);
    for (int p = 0; p < 3000; ++p) {
      // Points: near the particle centres of the sampler (box edges, corners, transition
      // nodes), some exactly on a node's grid line or at a node, all in the closed domain.
      double x, y, lx, ly;
      sample.draw(x, y, lx, ly, false);
      const double u = sample.U();
      if (u < 0.1) {
        x = g.X[sample.pick(act)];
      } else if (u < 0.2) {
        y = g.Y[sample.pick(act)];
      } else if (u < 0.25) {
        const PetscInt n = sample.pick(act);
        x = g.X[n];
        y = g.Y[n];
      }
      x = std::clamp(x, D[0], D[2]);
      y = std::clamp(y, D[1], D[3]);
      double s = 0, sx = 0, sy = 0, lo = 0, hi = 0;
      for (PetscInt n : act) {
        if (std::abs(g.X[n] - x) > h0 || std::abs(g.Y[n] - y) > h0) continue;
        const double *z = &g.zone[4 * n];
        const double w = tent(x - g.X[n], z[0], z[1]) * tent(y - g.Y[n], z[2], z[3]);
        s += w;
        sx += w * (g.X[n] - x);
        sy += w * (g.Y[n] - y);
        lo = std::min(lo, w);
        hi = std::max(hi, w);
      }
      auto where = [&] { return lay.name + ": " + at({{"x", x}, {"y", y}, {"sum", s}}); };
      unity.update(std::abs(s - 1.0), where);
      reproX.update(std::abs(sx) / h0, where);
      reproY.update(std::abs(sy) / h0, where);
      bounds.update(std::max(-lo, hi - 1.0), where);
    }
  }
  EXPECT_WORST_LE(unity, 1e-12);
  EXPECT_WORST_LE(reproX, 1e-12);
  EXPECT_WORST_LE(reproY, 1e-12);
  EXPECT_WORST_LE(bounds, 0.0);
}

// ---------------------------------------------------------------------------------------------
// 5. The gradient is the derivative of the weight: move the particle by +-eps in x and in y,
// rebuild the stencils and compare node by node (a node missing from a stencil has weight 0).

/// Entries of particle p of a stencil set, scattered into node-indexed arrays.
struct NodeValues {
  std::vector<double> w, gx, gy;
  std::vector<PetscInt> touched;
  explicit NodeValues(PetscInt n) : w(n, 0.0), gx(n, 0.0), gy(n, 0.0) {}
  void load(const Stencils &s, PetscInt p) {
    clear();
    for (PetscInt e = s.start[p]; e < s.start[p + 1]; ++e) {
      const PetscInt n = s.node[e];
      w[n] = s.w[0][e] * s.w[1][e];
      gx[n] = s.g[0][e] * s.w[1][e];
      gy[n] = s.w[0][e] * s.g[1][e];
      touched.push_back(n);
    }
  }
  void clear() {
    for (PetscInt n : touched)
      w[n] = gx[n] = gy[n] = 0.0;
    touched.clear();
  }
};

TEST(GridStencils, GradientMatchesFiniteDifference) {
  std::vector<Layout> layouts = twoLevelLayouts();
  for (const Layout &l : threeLevelLayouts())
    layouts.push_back(l);
  Worst fdX, fdY;
  long skipped = 0, total = 0;
  std::uint64_t seed = 0x6a1d3001;
  for (const Layout &lay : layouts) {
    const auto gp = makeGrid(sceneOf(lay));
    const Grid &g = *gp;
    const double hmin = g.hMin();
    Sampler sample(g, seed++);
    const long np = 20000 / static_cast<long>(layouts.size());
    std::vector<double> x(2 * np), l(2 * np), ex(np), ey(np);
    std::vector<double> xs[4];
    for (long p = 0; p < np; ++p) {
      // Away from domain edges by eps, so that the moved particles stay in the domain.
      do
        sample.draw(x[2 * p], x[2 * p + 1], l[2 * p], l[2 * p + 1], false);
      while (!insideDomain(g, x[2 * p], x[2 * p + 1], l[2 * p] + 1e-5 * hmin,
                           l[2 * p + 1] + 1e-5 * hmin));
      ex[p] = 1e-6 * std::min(l[2 * p], hmin);
      ey[p] = 1e-6 * std::min(l[2 * p + 1], hmin);
    }
    for (int d = 0; d < 4; ++d) {
      xs[d] = x;
      for (long p = 0; p < np; ++p)
        xs[d][2 * p + d / 2] += (d % 2 == 0 ? 1.0 : -1.0) * (d < 2 ? ex[p] : ey[p]);
    }
    Stencils base, moved[4];
    g.buildStencils(static_cast<PetscInt>(np), x.data(), l.data(), base);
    for (int d = 0; d < 4; ++d)
      g.buildStencils(static_cast<PetscInt>(np), xs[d].data(), l.data(), moved[d]);
    NodeValues b(g.nWindow), m[4] = {NodeValues(g.nWindow), NodeValues(g.nWindow),
                                     NodeValues(g.nWindow), NodeValues(g.nWindow)};
    for (long p = 0; p < np; ++p) {
      ++total;
      b.load(base, p);
      for (int d = 0; d < 4; ++d)
        m[d].load(moved[d], p);
      std::vector<PetscInt> nodes = b.touched;
      for (int d = 0; d < 4; ++d)
        nodes.insert(nodes.end(), m[d].touched.begin(), m[d].touched.end());
      std::sort(nodes.begin(), nodes.end());
      nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
      // The weight is a quadratic in x_p between the points where a particle edge crosses a
      // tent kink (X - Lx-, X, X + Lx+); a central difference over such a point is not exact,
      // so skip those few particles (continuity there is test 6).
      const double xp = x[2 * p], yp = x[2 * p + 1], lx = l[2 * p], ly = l[2 * p + 1];
      bool nearKink = false;
      double gmax = 0.0;
      for (PetscInt n : nodes) {
        const double *z = &g.zone[4 * n];
        for (double v : {g.X[n] - z[0], g.X[n], g.X[n] + z[1]})
          nearKink = nearKink || std::min(std::abs(xp - lx - v), std::abs(xp + lx - v)) < 4 * ex[p];
        for (double v : {g.Y[n] - z[2], g.Y[n], g.Y[n] + z[3]})
          nearKink = nearKink || std::min(std::abs(yp - ly - v), std::abs(yp + ly - v)) < 4 * ey[p];
        gmax = std::max({gmax, std::abs(b.gx[n]), std::abs(b.gy[n])});
      }
      if (nearKink) {
        ++skipped;
        continue;
      }
      double errX = 0.0, errY = 0.0;
      PetscInt worstNode = -1;
      for (PetscInt n : nodes) {
        const double fx = (m[0].w[n] - m[1].w[n]) / (2 * ex[p]);
        const double fy = (m[2].w[n] - m[3].w[n]) / (2 * ey[p]);
        if (std::abs(fx - b.gx[n]) > errX || std::abs(fy - b.gy[n]) > errY) worstNode = n;
        errX = std::max(errX, std::abs(fx - b.gx[n]));
        errY = std::max(errY, std::abs(fy - b.gy[n]));
      }
      auto where = [&] {
        return lay.name + ": " +
               at({{"xp", xp},
                   {"yp", yp},
                   {"lx", lx},
                   {"ly", ly},
                   {"node x", worstNode >= 0 ? g.X[worstNode] : 0.0},
                   {"node y", worstNode >= 0 ? g.Y[worstNode] : 0.0}});
      };
      fdX.update(errX / gmax, where);
      fdY.update(errY / gmax, where);
    }
  }
  EXPECT_WORST_LE(fdX, 1e-6);
  EXPECT_WORST_LE(fdY, 1e-6);
  std::printf("  skipped next to a kink: %ld of %ld\n", skipped, total);
  EXPECT_LT(skipped, total / 100);
}

// ---------------------------------------------------------------------------------------------
// 6. C1 continuity at transition nodes (paper Figs. 3 and 4(b)). A particle moves along a line
// through or next to a transition node, across the coarse-fine interface. Wherever one of its
// edges crosses a grid line, a zone end or an interface, the weights and gradients just before
// and just after (+-delta) must agree to the bound set by the sampling step: |dw/dx| <= 1/(2 l)
// and the gradient's own Lipschitz constants 1/(l Lmin) (along) and 1/(4 lx ly) (across). A jump
// of the weight or a kink of the weight (a jump of its gradient) would exceed them by ~1/delta.

TEST(GridContinuity, TransitionNodesAreC1) {
  std::vector<Layout> layouts;
  for (const Layout &l : twoLevelLayouts())
    if (l.name.rfind("middle", 0) == 0 || l.name.rfind("one cell", 0) == 0) layouts.push_back(l);
  for (const Layout &l : threeLevelLayouts())
    if (l.name.rfind("middle", 0) != 0) layouts.push_back(l);
  Worst jumpW, jumpG, jumpT;
  long events = 0, transitionSeen = 0;
  std::mt19937_64 rng(0x6a1d4001);
  for (const Layout &lay : layouts) {
    const auto gp = makeGrid(sceneOf(lay));
    const Grid &g = *gp;
    const double h0 = g.h0(), hmin = g.hMin(), delta = 1e-9 * hmin;
    const Box &D = g.levels[0].box;
    // Transition nodes: active, zones other than their level's h, not on the domain edge.
    std::vector<PetscInt> trans;
    for (PetscInt n = 0; n < g.nWindow; ++n)
      if (g.active[n] && !g.regular[n] && g.X[n] > D[0] && g.X[n] < D[2] && g.Y[n] > D[1] &&
          g.Y[n] < D[3])
        trans.push_back(n);
    std::shuffle(trans.begin(), trans.end(), rng);
    if (trans.size() > 24) trans.resize(24);
    ASSERT_FALSE(trans.empty());
    NodeValues va(g.nWindow), vb(g.nWindow);
    for (PetscInt t : trans) {
      const double *zt = &g.zone[4 * t];
      const double zmin = std::min({zt[0], zt[1], zt[2], zt[3]});
      for (int axis = 0; axis < 2; ++axis) {
        const double *P = axis == 0 ? g.X.data() : g.Y.data(); // along the line
        const double *Q = axis == 0 ? g.Y.data() : g.X.data(); // across
        const double zm = zt[2 * axis], zp = zt[2 * axis + 1];
        const double qm = zt[2 - 2 * axis], qp = zt[3 - 2 * axis];
        for (double la : {0.5 * zmin, 0.37 * h0, 0.5 * h0})
          for (double off : {0.0, 0.3 * qp, -0.45 * qm}) {
            const double lb = 0.8 * la, across = Q[t] + off;
            // Events: particle edges on a node's line or on the ends of its zone, for the nodes
            // near the line.
            const double lo = P[t] - zm - la - h0, hi = P[t] + zp + la + h0;
            std::vector<double> ev;
            for (PetscInt n = 0; n < g.nWindow; ++n) {
              if (!g.active[n] || std::abs(Q[n] - across) > lb + h0 || P[n] < lo - h0 ||
                  P[n] > hi + h0)
                continue;
              const double *z = &g.zone[4 * n];
              for (double v : {P[n] - z[2 * axis], P[n], P[n] + z[2 * axis + 1]})
                for (double e : {v - la, v + la})
                  if (e > lo && e < hi) ev.push_back(e);
            }
            std::sort(ev.begin(), ev.end());
            ev.erase(std::unique(ev.begin(), ev.end(),
                                 [&](double a, double b) { return b - a < 1e-12 * h0; }),
                     ev.end());
            // Pairs of particles at e -+ delta, all in one call.
            std::vector<double> xs, ls, es;
            for (double e : ev) {
              bool in = true;
              for (double s : {-delta, delta}) {
                const double pa = e + s;
                const double x = axis == 0 ? pa : across, y = axis == 0 ? across : pa;
                in = in && insideDomain(g, x, y, axis == 0 ? la : lb, axis == 0 ? lb : la);
              }
              if (!in) continue;
              es.push_back(e);
              for (double s : {-delta, delta}) {
                const double pa = e + s;
                xs.push_back(axis == 0 ? pa : across);
                xs.push_back(axis == 0 ? across : pa);
                ls.push_back(axis == 0 ? la : lb);
                ls.push_back(axis == 0 ? lb : la);
              }
            }
            if (es.empty()) continue;
            Stencils s;
            g.buildStencils(static_cast<PetscInt>(xs.size() / 2), xs.data(), ls.data(), s);
            const double tolW = 2 * delta / (2 * la);
            const double tolAlong = 2 * delta / (la * hmin), tolAcross = 2 * delta / (4 * la * lb);
            for (size_t k = 0; k < es.size(); ++k) {
              va.load(s, static_cast<PetscInt>(2 * k));
              vb.load(s, static_cast<PetscInt>(2 * k + 1));
              std::vector<PetscInt> nodes = va.touched;
              nodes.insert(nodes.end(), vb.touched.begin(), vb.touched.end());
              double jw = 0, jg = 0;
              PetscInt worst = -1;
              for (PetscInt n : nodes) {
                const double ga = axis == 0 ? va.gx[n] : va.gy[n];
                const double gb = axis == 0 ? vb.gx[n] : vb.gy[n];
                const double ca = axis == 0 ? va.gy[n] : va.gx[n];
                const double cb = axis == 0 ? vb.gy[n] : vb.gx[n];
                const double w = std::abs(vb.w[n] - va.w[n]) / tolW;
                const double gr =
                    std::max(std::abs(gb - ga) / tolAlong, std::abs(cb - ca) / tolAcross);
                if (w > jw || gr > jg) worst = n;
                jw = std::max(jw, w);
                jg = std::max(jg, gr);
                if (n == t) {
                  jumpT.update(std::max(w, gr), [&] {
                    return lay.name + ": " +
                           at({{"node x", g.X[t]},
                               {"node y", g.Y[t]},
                               {"axis", axis},
                               {"edge at", es[k]},
                               {"across", across},
                               {"l", la}});
                  });
                  transitionSeen += va.w[n] > 0.0 || vb.w[n] > 0.0;
                }
              }
              ++events;
              auto where = [&] {
                return lay.name + ": " +
                       at({{"transition x", g.X[t]},
                           {"transition y", g.Y[t]},
                           {"axis", axis},
                           {"particle at", es[k]},
                           {"across", across},
                           {"l along", la},
                           {"l across", lb},
                           {"node x", worst >= 0 ? g.X[worst] : 0.0},
                           {"node y", worst >= 0 ? g.Y[worst] : 0.0}});
              };
              jumpW.update(jw, where);
              jumpG.update(jg, where);
            }
          }
      }
    }
  }
  // Jumps in units of the bound: <= 1 for a C1 weight (the bound along the line is attained, so
  // allow 1% for round-off), ~1e9 for a jump of the weight or of its gradient.
  EXPECT_WORST_LE(jumpW, 1.01);
  EXPECT_WORST_LE(jumpG, 1.01);
  EXPECT_WORST_LE(jumpT, 1.01);
  std::printf("  events %ld, with the transition node's weight nonzero %ld\n", events,
              transitionSeen);
  EXPECT_GT(transitionSeen, events / 10);
}

// ---------------------------------------------------------------------------------------------
// 7. Badly nested layouts are rejected with a one-line InputError that names the option of the
// offending level and gives the documented reason (docs/method.md, "Levels"; docs/options.md):
// a corner off the parent's grid lines, an empty box, or a box not inside its parent. Any
// InputError is not enough: a layout rejected for the wrong reason (say a box inside its parent
// reported as not nested) means the check that should have caught it did not.

/// The scene is rejected; the message is one line, names `option` and contains `reason`.
void expectRejected(const Scene &sc, const char *what, const std::string &option,
                    const char *reason) {
  Grid g;
  try {
    g.setGeometry(sc);
    ADD_FAILURE() << what << ": accepted";
  } catch (const InputError &e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << what << ": " << msg;
    EXPECT_NE(msg.find("option " + option + " "), std::string::npos)
        << what << ": does not name " << option << ": " << msg;
    EXPECT_NE(msg.find(reason), std::string::npos)
        << what << ": not rejected for \"" << reason << "\": " << msg;
    std::printf("  %-40s %s\n", what, msg.c_str());
  } catch (const std::exception &e) {
    ADD_FAILURE() << what << ": not an InputError: " << e.what();
  }
}

TEST(GridLayout, BadLayoutsRejected) {
  const Box dom = {0, 0, 8, 6};
  const std::string L0 = "-gimp_level0_box", L1 = "-gimp_level1_box", L2 = "-gimp_level2_box";
  // Corner off the parent's grid lines.
  expectRejected(plainScene(dom, 2, {{{3, 2, 6, 6}, 2}}), "level-1 corner off level-0 lines", L1,
                 "corner coordinate 3 is not on a grid line of level 0");
  expectRejected(plainScene(dom, 2, {{{2, 2, 6, 5}, 2}}), "level-1 corner y off level-0 lines", L1,
                 "corner coordinate 5 is not on a grid line of level 0");
  expectRejected(plainScene(dom, 2, {{{2, 2, 6, 6}, 2}, {{2.5, 3, 4, 5}, 2}}),
                 "level-2 corner on its own lines only", L2,
                 "corner coordinate 2.5 is not on a grid line of level 1");
  expectRejected(plainScene(dom, 2, {{{2, 2, 6, 6}, 3}, {{2, 3, 4, 5}, 2}}),
                 "level-2 corner off level-1 lines (r=3)", L2,
                 "corner coordinate 3 is not on a grid line of level 1");
  // Domain not a whole number of level-0 cells.
  expectRejected(plainScene({0, 0, 9, 6}, 2, {}), "domain width not a multiple of h", L0,
                 "corner coordinate 9 is not on a grid line of level 0");
  // Box outside its parent.
  expectRejected(plainScene(dom, 2, {{{6, 2, 10, 6}, 2}}), "level-1 box beyond the domain", L1,
                 kNotInside);
  expectRejected(plainScene(dom, 2, {{{10, 2, 12, 4}, 2}}), "level-1 box outside the domain", L1,
                 kNotInside);
  expectRejected(plainScene(dom, 2, {{{-2, 2, 2, 4}, 2}}), "level-1 box left of the domain", L1,
                 kNotInside);
  expectRejected(plainScene(dom, 2, {{{-4, 2, 2, 4}, 2}}), "level-1 box far left of the domain", L1,
                 kNotInside);
  expectRejected(plainScene(dom, 2, {{{2, 2, 4, 4}, 2}, {{3, 3, 5, 4}, 2}}),
                 "level-2 box crossing level 1's edge", L2, "not inside level 1's box");
  expectRejected(plainScene(dom, 2, {{{2, 2, 4, 4}, 2}, {{5, 3, 6, 4}, 2}}),
                 "level-2 box outside level 1", L2, "not inside level 1's box");
  // Non-positive extent.
  expectRejected(plainScene(dom, 2, {{{2, 2, 2, 6}, 2}}), "level-1 box of zero width", L1, kEmpty);
  expectRejected(plainScene(dom, 2, {{{6, 2, 2, 6}, 2}}), "level-1 box of negative width", L1,
                 kEmpty);
  expectRejected(plainScene(dom, 2, {{{2, 4, 6, 4}, 2}}), "level-1 box of zero height", L1, kEmpty);
  expectRejected(plainScene(dom, 2, {{{2, 2, 6, 6}, 2}, {{3, 4, 4, 3}, 2}}),
                 "level-2 box of negative height", L2, kEmpty);
  expectRejected(plainScene({0, 0, 0, 6}, 2, {}), "domain of zero width", L0, kEmpty);

  // The layouts of tests 2-6 are all valid and all accepted: 15 two-level and 36 three-level.
  int accepted = 0, tried = 0;
  for (const std::vector<Layout> &family : {twoLevelLayouts(), threeLevelLayouts()})
    for (const Layout &lay : family) {
      ++tried;
      Grid g;
      try {
        g.setGeometry(sceneOf(lay));
        ++accepted;
      } catch (const InputError &e) {
        ADD_FAILURE() << lay.name << ": rejected: " << e.what();
      }
    }
  EXPECT_EQ(tried, 15 + 36);
  EXPECT_EQ(accepted, tried);
}

} // namespace
