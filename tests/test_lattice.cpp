// Unit tests of the composite grid in include/gimp/grid/grid.hpp (paper section 3), its lattice:
// nested uniform levels, active nodes, influence zones [Lx-, Lx+, Ly-, Ly+] and which layouts are
// valid. (The GIMP stencils on the same layouts: test_stencils.cpp and
// test_stencil_smoothness.cpp.)
//
//   1. The paper's Fig. 2 grid: zones of named nodes, inactive coarse nodes, active node counts.
//   2. Every location carries exactly one active node, with zones of leaf-cell widths.
//   3. Badly nested layouts are rejected with an InputError naming the option and the
//      documented reason; the layouts of test 2 and of the stencil tests are all accepted.
//      (Deeper layouts, valid and invalid: GridStencils.DeepRefinementLayouts.)
#include "gimp/grid/grid.hpp"

#include "grid_layouts.hpp"
#include "test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace {

using gimp::test::kEmpty;
using gimp::test::kNotInside;
using gimp::test::Layout;
using gimp::test::makeGrid;
using gimp::test::plainScene;
using gimp::test::sceneOf;
using gimp::test::threeLevelLayouts;
using gimp::test::twoLevelLayouts;

using gimp::BoxOf;
using gimp::Grid;
using gimp::InputError;
using gimp::Level;
using gimp::Scene;

/// Level of window node n.
int levelOf(const Grid<2> &g, PetscInt n) {
  int k = 0;
  while (k + 1 < static_cast<int>(g.levels.size()) && n >= g.levels[k + 1].offset)
    ++k;
  return k;
}

/// Window index of level k's node (i, j).
PetscInt windowIndex(const Grid<2> &g, int k, PetscInt i, PetscInt j) {
  const Level<2> &L = g.levels[k];
  return L.offset + (j - L.w0[1]) * L.wnx() + (i - L.w0[0]);
}

/// Active window nodes at (x, y).
std::vector<PetscInt> activeAt(const Grid<2> &g, double x, double y) {
  std::vector<PetscInt> v;
  const double tol = 1e-9 * g.hMin();
  for (PetscInt n = 0; n < g.nWindow; ++n)
    if (g.active[n] && std::abs(g.X[n] - x) < tol && std::abs(g.Y[n] - y) < tol) v.push_back(n);
  return v;
}

// ---------------------------------------------------------------------------------------------
// 1. The paper's Fig. 2: coarse grid (0,0)-(8,6) with h = 2, fine box (2,2)-(6,6), ratio 2.

/// The single active node at (x, y) has level k and zones z (checked in the window data and by
/// the pure-geometry zonesOf).
void expectNode(const Grid<2> &g, double x, double y, int k, std::array<double, 4> z) {
  const std::vector<PetscInt> n = activeAt(g, x, y);
  ASSERT_EQ(n.size(), 1u) << "active nodes at (" << x << ", " << y << ")";
  EXPECT_EQ(levelOf(g, n[0]), k) << "(" << x << ", " << y << ")";
  const Level<2> &L = g.levels[k];
  const auto i = static_cast<PetscInt>(std::llround((x - L.box[0]) / L.h));
  const auto j = static_cast<PetscInt>(std::llround((y - L.box[1]) / L.h));
  EXPECT_TRUE(g.nodeActive(k, {i, j}));
  double zg[4];
  g.zonesOf(k, {i, j}, zg);
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
      EXPECT_EQ(g->nodeActive(0, {i, j}), !covered) << "coarse node " << i << "," << j;
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
      EXPECT_EQ(g->nodeActive(0, {i, j}), !covered) << "coarse node " << i << "," << j;
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
    const BoxOf<2> &D = g->levels[0].box;
    // Finest-lattice coordinates of every node, and the active copies there.
    std::map<std::pair<std::int64_t, std::int64_t>, int> activeCount;
    std::int64_t activeTotal = 0;
    std::set<double> widths;
    for (const Level<2> &L : g->levels)
      widths.insert(L.h);
    for (int k = 0; k < K; ++k) {
      const Level<2> &L = g->levels[k];
      ASSERT_EQ(L.wnx() * (L.w1[1] - L.w0[1]),
                L.n[0] * L.n[1]); // one rank: the window is everything
      for (PetscInt j = 0; j < L.n[1]; ++j)
        for (PetscInt i = 0; i < L.n[0]; ++i) {
          const PetscInt n = windowIndex(*g, k, i, j);
          const auto key = std::make_pair(L.lo[0] + i * L.step, L.lo[1] + j * L.step);
          activeCount[key] += g->active[n];
          EXPECT_EQ(g->active[n] != 0, g->nodeActive(k, {i, j}));
          if (!g->active[n]) {
            // An inactive node lies in the closed box of a finer level.
            bool covered = false;
            for (int q = k + 1; q < K; ++q) {
              const Level<2> &F = g->levels[q];
              covered = covered || (key.first >= F.lo[0] && key.first <= F.hi[0] &&
                                    key.second >= F.lo[1] && key.second <= F.hi[1]);
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
// 3. Badly nested layouts are rejected with a one-line InputError that names the option of the
// offending level and gives the documented reason (docs/method.md, "Levels"; docs/options.md):
// a corner off the parent's grid lines, an empty box, or a box not inside its parent. Any
// InputError is not enough: a layout rejected for the wrong reason (say a box inside its parent
// reported as not nested) means the check that should have caught it did not.

/// The scene is rejected; the message is one line, names `option` and contains `reason`.
void expectRejected(const Scene<2> &sc, const char *what, const std::string &option,
                    const char *reason) {
  Grid<2> g;
  try {
    g.setLevels(sc.h, sc.levelBoxes());
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
  const BoxOf<2> dom = {0, 0, 8, 6};
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

  // The layouts of test 2, test_stencils.cpp and test_stencil_smoothness.cpp are all valid and
  // all accepted: 15 two-level and 36 three-level.
  int accepted = 0, tried = 0;
  for (const std::vector<Layout> &family : {twoLevelLayouts(), threeLevelLayouts()})
    for (const Layout &lay : family) {
      ++tried;
      Grid<2> g;
      try {
        {
          const auto sc = sceneOf(lay);
          g.setLevels(sc.h, sc.levelBoxes());
        }
        ++accepted;
      } catch (const InputError &e) {
        ADD_FAILURE() << lay.name << ": rejected: " << e.what();
      }
    }
  EXPECT_EQ(tried, 15 + 36);
  EXPECT_EQ(accepted, tried);
}

} // namespace
