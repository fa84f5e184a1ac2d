// Unit tests of the GIMP stencils of particles on the composite grid in include/gimp/grid/grid.hpp
// (paper section 3): the weights and gradients buildStencils gives and the point shape
// functions, on the refined layouts of grid_layouts.hpp. (The lattice itself: test_lattice.cpp;
// derivatives and continuity of the weights: test_stencil_smoothness.cpp.)
//
//   1. Particle weights on 2- and 3-level grids with ratios 2, 3 and 4 (boxes in the middle,
//      on the domain edge, on the parent's edge, sharing corners, coinciding): partition of
//      unity, linear reproduction and their derivatives. 1a: deeper refinement (up to 8
//      levels, total ratio up to 128, particles up to a whole level-0 cell): the valid layouts
//      are accepted and give the same identities, the invalid ones are rejected for the
//      documented reason. 1b: particles whose edge lies exactly on the domain edge.
//   1c. With a crack (and a disk where it may grow): the blocks of the compact path equal the
//      rows with every crossing segment's entry re-addressed, particle by particle, before and
//      after the crack grows, with the nodes marked for the particles' largest half-size
//      (Grid::liveReachFor; smaller particles mark fewer nodes).
//   1d. The release of a grown increment (cracks::Contact with a release time): the nodes the
//      increment newly cut, and only those, have their fields' relative velocity scaled by the
//      elapsed fraction of the release, momentum kept, accelerations alike.
//   2. The point shape functions (tent products with each node's zones) on the same grids.
//
// All random sampling uses a fixed-seed std::mt19937_64, so every run checks the same points.
// Random checks keep the largest error and report where (layout and particle) it occurred.
#include "gimp/cracks/fields.hpp"
#include "gimp/grid/crack_fields.hpp"
#include "gimp/grid/grid.hpp"
#include "gimp/grid/shape.hpp"
#include "gimp/transfer/lane_loops.hpp"
#include "gimp/transfer/transfer.hpp"

#include "grid_layouts.hpp"
#include "test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using gimp::test::at;
using gimp::test::Worst;

using gimp::test::BoxSpec;
using gimp::test::kEmpty;
using gimp::test::kH0;
using gimp::test::kNotInside;
using gimp::test::kOffLines;
using gimp::test::Layout;
using gimp::test::makeGrid;
using gimp::test::Sampler;
using gimp::test::sceneOf;
using gimp::test::threeLevelLayouts;
using gimp::test::twoLevelLayouts;

using gimp::BoxOf;
using gimp::Grid;
using gimp::InputError;
using gimp::Level;
using Stencils = gimp::Stencils<2>;
using gimp::shape::tent;

// ---------------------------------------------------------------------------------------------
// ---------------------------------------------------------------------------------------------
// 1. Particle weights on the composite grid.

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
  const Grid<2> &g = *gp;
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

// 1a. Deeper refinement: up to the scene's 8 levels, ratios up to its maximum 16, total ratios
// up to 128, and particles up to a whole level-0 cell (half-size h0, the largest a run allows).
// Every layout is classified in advance. A layout whose corners lie on its parent's grid lines
// (to the relative tolerance 1e-9 of setLevels, docs/options.md), with a non-empty box inside
// its parent, is valid (docs/method.md, "Levels"): it must be accepted and give the identities
// of test 1 with the same tolerances and sampling coverage. Any other layout must be rejected
// with a one-line InputError that names the offending level's option and gives the documented
// reason. (The ratio range 2..16 and the level count 1..8 are the scene parser's checks, not
// setLevels's.) An earlier version skipped every rejected layout, so a setLevels that
// rejected everything passed.

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
      Grid<2> probe;
      try {
        {
          const auto sc = sceneOf(c.lay);
          probe.setLevels(sc.h, sc.levelBoxes());
        }
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

// 1b. Particles whose edge lies on the domain edge, as seeding makes them for a body that ends on
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
        const Grid<2> &g = *gp;
        const BoxOf<2> &D = g.levels[0].box;
        std::vector<double> x, l;
        for (int n : {1, 2, 3})
          for (size_t q = 0; q < g.levels.size(); ++q) {
            const Level<2> &L = g.levels[q];
            const double d = L.h / n;
            for (PetscInt j = 0; j + 1 < L.n[1]; ++j)
              for (PetscInt i = 0; i + 1 < L.n[0]; ++i) {
                const double cx0 = L.box[0] + i * L.h, cy0 = L.box[1] + j * L.h;
                if (g.leafLevelAt(cx0 + 0.5 * L.h, cy0 + 0.5 * L.h) != static_cast<int>(q))
                  continue;
                for (int b = 0; b < n; ++b)
                  for (int a = 0; a < n; ++a) {
                    const bool edge = (i == 0 && a == 0 && cx0 == D[0]) ||
                                      (j == 0 && b == 0 && cy0 == D[1]) ||
                                      (i + 2 == L.n[0] && a + 1 == n && L.box[2] == D[2]) ||
                                      (j + 2 == L.n[1] && b + 1 == n && L.box[3] == D[3]);
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
// 1c. Blocks beside a crack.

/// Per particle: slot -> (weight, d/dx, d/dy) of its stencil as forEach reads it.
std::vector<std::map<PetscInt, std::array<double, 3>>> entriesOf(const Stencils &s, long np) {
  std::vector<std::map<PetscInt, std::array<double, 3>>> out(np);
  for (long p = 0; p < np; ++p)
    s.forEach(p, [&](PetscInt slot, double w, const gimp::Vector<2> &g) {
      auto &e = out[p][slot];
      e[0] += w;
      e[1] += g[0];
      e[2] += g[1];
    });
  return out;
}

/// The differences of one particle's entries in two stencil forms (entriesOf) into weight and
/// gradient (times h0). Either form may list a node the particle's edge reaches with weight 0
/// (or 1e-30) that the other leaves out: compare over both lists, a missing entry as 0.
template <class Where>
void compareEntries(const std::map<PetscInt, std::array<double, 3>> &r,
                    const std::map<PetscInt, std::array<double, 3>> &b, double h0,
                    const Where &where, Worst &weight, Worst &gradient) {
  auto diff = [&](const auto &a, const auto &o) {
    for (const auto &[slot, e] : a) {
      const auto it = o.find(slot);
      const std::array<double, 3> f = it == o.end() ? std::array<double, 3>{} : it->second;
      weight.update(std::abs(e[0] - f[0]), where);
      gradient.update(std::max(std::abs(e[1] - f[1]), std::abs(e[2] - f[2])) * h0, where);
    }
  };
  diff(r, b);
  diff(b, r);
}

// ---------------------------------------------------------------------------------------------
// 1d. Blocks beside box faces and the domain's edges: a block whose first or last node has a
// zone other than h on its far side (a finer box's face node, whose outward zone is the coarser
// cell, or a domain-edge node, zone 0 outside) gives its particles the weights of their rows.

TEST(GridStencils, BlocksBesideFacesEqualRows) {
  std::vector<Layout> layouts = twoLevelLayouts();
  for (const Layout &lay : threeLevelLayouts())
    layouts.push_back(lay);
  long compared = 0, blocks = 0, beside = 0;
  Worst weight, gradient;
  std::uint64_t seed = 0x6a1d0f00;
  for (const Layout &lay : layouts) {
    const auto gp = makeGrid(sceneOf(lay));
    const Grid<2> &g = *gp;
    const double h0 = g.h0();
    Sampler sample(g, seed++);
    const long np = 3000;
    std::vector<double> x(2 * np), l(2 * np);
    for (long p = 0; p < np; ++p) // half-sizes up to h0 / 2: blocks of 3 and of 4 nodes
      sample.draw(x[2 * p], x[2 * p + 1], l[2 * p], l[2 * p + 1], true, 0.5 * h0);
    Stencils rows, compact;
    ASSERT_TRUE(g.buildStencils(np, x.data(), l.data(), rows, false));
    ASSERT_TRUE(g.buildStencils(np, x.data(), l.data(), compact, true, true));
    const auto r = entriesOf(rows, np), b = entriesOf(compact, np);
    for (long p = 0; p < np; ++p) {
      const bool block = compact.isBlock(p) || compact.isBlock4(p);
      blocks += block;
      bool irregular = false;
      for (const auto &[slot, e] : b[p])
        irregular = irregular || !g.regular[slot];
      beside += block && irregular;
      const auto where = [&] {
        return lay.name + ": " +
               at({{"xp", x[2 * p]}, {"yp", x[2 * p + 1]}, {"lx", l[2 * p]}, {"ly", l[2 * p + 1]}});
      };
      compareEntries(r[p], b[p], h0, where, weight, gradient);
      ++compared;
    }
  }
  std::printf("  particles %ld: blocks %ld, %ld of them with a node not regular on both sides\n",
              compared, blocks, beside);
  // The closed forms divide the tent integrals by 2 l: round-off of about eps h / l (particles
  // down to a few hundredths of h here); a block with a wrong node is off by 1e-3 or more.
  EXPECT_WORST_LE(weight, 1e-13);
  EXPECT_WORST_LE(gradient, 1e-12);
  EXPECT_GT(blocks, compared / 10);
  EXPECT_GT(beside, blocks / 20);
}

// ---------------------------------------------------------------------------------------------
// 1d'. Lane groups of one block: the four particles of a cell (two per axis, half-size h / 4)
// moved together by up to a quarter cell, so that one particle's domain crosses a cell line while
// the other's ends inside the cell. Their blocks started one node apart; the stencil build starts
// the later one a node earlier with a zero first factor (alignedStarts), so that the group is one
// block. Every particle keeps its rows' entries, and almost every group is one block.

TEST(GridStencils, LaneGroupsOfOneBlockEqualRows) {
  namespace lanes = gimp::transfer::laneLoops;
  std::vector<Layout> layouts = twoLevelLayouts();
  for (const Layout &lay : threeLevelLayouts())
    layouts.push_back(lay);
  long compared = 0, groups = 0, laneGroups = 0, oneBlock = 0;
  Worst weight, gradient;
  std::mt19937_64 rng(0x6a1d0f0b);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (const Layout &lay : layouts) {
    const auto gp = makeGrid(sceneOf(lay));
    const Grid<2> &g = *gp;
    const BoxOf<2> &D = g.levels[0].box;
    std::vector<double> x, l;
    while (x.size() < 2 * 4 * 800) {
      double c[2] = {D[0] + U(rng) * (D[2] - D[0]), D[1] + U(rng) * (D[3] - D[1])};
      const Level<2> &L = g.levels[g.leafLevelAt(c[0], c[1])];
      double shift[2], p[4][2];
      for (int a = 0; a < 2; ++a) {
        c[a] = L.box[a] + std::floor((c[a] - L.box[a]) / L.h) * L.h; // the cell's first corner
        shift[a] = (U(rng) - 0.5) * 0.5 * L.h;
      }
      bool inside = true;
      for (int q = 0; q < 4; ++q) {
        for (int a = 0; a < 2; ++a) // (a little strain: each particle off by up to h / 50)
          p[q][a] =
              c[a] + ((q >> a) & 1 ? 0.75 : 0.25) * L.h + shift[a] + (U(rng) - 0.5) * 0.04 * L.h;
        inside = inside && gimp::test::insideDomain(g, p[q][0], p[q][1], 0.25 * L.h, 0.25 * L.h);
      }
      if (!inside) continue;
      for (int q = 0; q < 4; ++q)
        for (int a = 0; a < 2; ++a) {
          x.push_back(p[q][a]);
          l.push_back(0.25 * L.h);
        }
    }
    const long np = static_cast<long>(x.size() / 2);
    Stencils rows, compact;
    ASSERT_TRUE(g.buildStencils(np, x.data(), l.data(), rows, false));
    ASSERT_TRUE(g.buildStencils(np, x.data(), l.data(), compact, true, true));
    for (long q = 0; q + 4 <= np; q += 4) {
      const std::uint8_t group = compact.laneGroupOf(q / 4);
      ++groups;
      laneGroups += group != 0;
      oneBlock += group != 0 && (group & 7) == 0;
    }
    const auto r = entriesOf(rows, np), b = entriesOf(compact, np);
    for (long p = 0; p < np; ++p) {
      const auto where = [&] {
        return lay.name + ": " + at({{"xp", x[2 * p]}, {"yp", x[2 * p + 1]}, {"l", l[2 * p]}});
      };
      compareEntries(r[p], b[p], g.h0(), where, weight, gradient);
      ++compared;
    }
  }
  std::printf("  particles %ld; groups %ld: %ld in lanes, %ld of them one block\n", compared,
              groups, laneGroups, oneBlock);
  EXPECT_WORST_LE(weight, 1e-13);
  EXPECT_WORST_LE(gradient, 1e-12);
  if (!lanes::available()) GTEST_SKIP() << "no AVX2 here: no lane groups";
  // Lane groups are those inside one level's regular nodes (about a third here: the layouts'
  // boxes are a few cells wide). Without the earlier starts about three in four of them would
  // hold two or four blocks; with them only groups whose strain (the h / 50 offsets) spreads
  // their domains over four nodes along an axis (a few in a hundred) keep more than one.
  EXPECT_GT(laneGroups, 1000);
  EXPECT_GT(oneBlock, laneGroups * 9 / 10);
}

// ---------------------------------------------------------------------------------------------
// 1e. The FLIP/PIC transfers in lanes of four block particles (src/transfer/lane_loops_flip.cpp,
// built without contraction) give the scalar loops' values bit for bit: P2G of momentum and
// mass, G2P with and without the re-projection, and a rate class's G2P, on stencils with lane
// groups, blocks of 4 nodes and rows among them.

TEST(GridStencils, FlipLanesEqualScalarLoops) {
  namespace lanes = gimp::transfer::laneLoops;
  if (!lanes::available()) GTEST_SKIP() << "no AVX2 here: the lanes do not run";
  long groups = 0, particles = 0;
  std::uint64_t seed = 0x6a1d0f1a;
  for (const Layout &lay : {twoLevelLayouts()[0], threeLevelLayouts()[0]}) {
    const auto gp = makeGrid(sceneOf(lay));
    const Grid<2> &g = *gp;
    Sampler sample(g, seed++);
    const long np = 4003; // (a tail after the last group of four)
    std::vector<double> x(2 * np), l(2 * np);
    for (long p = 0; p < np; ++p) // mostly 3-node blocks, some 4-node blocks and rows
      sample.draw(x[2 * p], x[2 * p + 1], l[2 * p], l[2 * p + 1], true,
                  p >= np - np / 7 ? 0.5 * g.h0() : 0.2 * g.h0());
    { // ordered by the level that holds them, as a run's cell order does: lane groups form
      std::vector<std::pair<int, long>> key(np);
      for (long p = 0; p < np; ++p)
        key[p] = {g.coarsestReaching(&x[2 * p], &l[2 * p]), p};
      std::stable_sort(key.begin(), key.end(),
                       [](const auto &a, const auto &b) { return a.first < b.first; });
      const std::vector<double> x0 = x, l0 = l;
      for (long p = 0; p < np; ++p)
        for (int a = 0; a < 2; ++a) {
          x[2 * p + a] = x0[2 * key[p].second + a];
          l[2 * p + a] = l0[2 * key[p].second + a];
        }
    }
    Stencils st;
    ASSERT_TRUE(g.buildStencils(np, x.data(), l.data(), st, true, true));
    for (long q = 0; q + 4 <= np; q += 4)
      groups += st.laneGroupOf(q / 4) != 0;
    particles += np;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    const size_t nv = 2 * static_cast<size_t>(g.nSlots);
    std::vector<double> vg(nv), ag(nv), m(np), v(2 * np);
    for (double &a : vg)
      a = U(rng);
    for (double &a : ag)
      a = 1e3 * U(rng);
    for (double &a : m)
      a = 1.0 + 0.5 * U(rng);
    for (double &a : v)
      a = U(rng);
    const double dt = 1e-4, flip = 0.95;
    // Each kernel on copies of the same state: scalar (a), lanes (b).
    auto same = [&](const std::vector<double> &a, const std::vector<double> &b, const char *what) {
      long differ = 0;
      for (size_t i = 0; i < a.size(); ++i)
        differ += a[i] != b[i];
      EXPECT_EQ(differ, 0) << lay.name << ": " << what;
    };
    {
      std::vector<double> ma(nv, 0.0), mb(nv, 0.0), sa(nv, 0.0), sb(nv, 0.0);
      gimp::transfer::particlesToGrid<2>(st, np, m.data(), v.data(), ma.data(), sa.data());
      lanes::particlesToGrid(st, np, m.data(), v.data(), mb.data(), sb.data());
      same(ma, mb, "P2G momentum");
      same(sa, sb, "P2G mass");
    }
    {
      std::vector<double> va = v, vb = v, xa = x, xb = x, ma(nv, 0.0), mb(nv, 0.0);
      gimp::transfer::gridToParticlesProjected<2>(st, np, vg.data(), ag.data(), dt, flip, m.data(),
                                                  va.data(), xa.data(), ma.data());
      lanes::gridToParticlesProjected(st, np, vg.data(), ag.data(), dt, flip, m.data(), vb.data(),
                                      xb.data(), mb.data());
      same(va, vb, "G2P (MUSL) velocities");
      same(xa, xb, "G2P (MUSL) positions");
      same(ma, mb, "G2P (MUSL) re-projection");
    }
    {
      std::vector<double> va = v, vb = v, xa = x, xb = x;
      gimp::transfer::gridToParticles<2>(st, np, vg.data(), ag.data(), dt, flip, va.data(),
                                         xa.data());
      lanes::gridToParticles(st, np, vg.data(), ag.data(), dt, flip, vb.data(), xb.data());
      same(va, vb, "G2P (USL) velocities");
      same(xa, xb, "G2P (USL) positions");
    }
    for (const bool project : {true, false}) {
      std::vector<double> va = v, vb = v, xa = x, xb = x, ma(nv, 0.0), mb(nv, 0.0);
      gimp::transfer::gridToParticlesRated<2>(st, np, ag.data(), vg.data(), 4 * dt, flip, m.data(),
                                              va.data(), xa.data(), project ? ma.data() : nullptr);
      lanes::gridToParticlesRated(st, np, ag.data(), vg.data(), 4 * dt, flip, m.data(), vb.data(),
                                  xb.data(), project ? mb.data() : nullptr);
      same(va, vb, "rated G2P velocities");
      same(xa, xb, "rated G2P positions");
      same(ma, mb, "rated G2P re-projection");
    }
  }
  std::printf("  %ld particles, %ld lane groups of four\n", particles, groups);
  EXPECT_GE(groups, 40); // (the lanes did run: the sampler draws many particles beside borders)
}

TEST(GridStencils, CrackedBlocksEqualRows) {
  // A kinked crack from outside the domain's left edge into the fine box, and a disk around its
  // tip where it may grow: the disk's nodes get second fields the crack does not reach yet.
  long blocks = 0, blocksBesideReserve = 0, readdressed = 0, compared = 0, marked[2] = {0, 0};
  Worst weight, gradient;
  for (const Layout &lay : twoLevelLayouts()) {
    gimp::Scene<2> sc = sceneOf(lay);
    const BoxOf<2> D = sc.levelBoxes()[0].box;
    const double h0 = sc.h, W = D[2] - D[0], H = D[3] - D[1];
    gimp::Crack c;
    c.points = {{D[0] - 0.3 * h0, D[1] + 0.52 * H},
                {D[0] + 0.31 * W, D[1] + 0.49 * H},
                {D[0] + 0.47 * W, D[1] + 0.56 * H}};
    sc.cracks = {c};
    for (int pass = 0; pass < 4; ++pass) {
      // Passes 1 and 3: the tip has advanced into the reserve, where new nodes are reached.
      // Passes 2 and 3: particles up to 0.3 times the size, and the reach marked for them.
      const bool grown = pass % 2 == 1, small = pass >= 2;
      if (pass == 1) sc.cracks[0].points.push_back({D[0] + 0.61 * W, D[1] + 0.50 * H});
      Grid<2> g;
      g.crackReserve.push_back({D[0] + 0.47 * W, D[1] + 0.56 * H, 0.3 * W});
      // Built with the crack as it was, then told that it grew (as a run does).
      ASSERT_EQ(static_cast<int>(g.create(PETSC_COMM_SELF, h0, sc.levelBoxes(),
                                          grown ? std::vector<gimp::Crack>{c} : sc.cracks)),
                0);
      ASSERT_GT(g.nSlots, g.nWindow) << lay.name;
      Sampler sample(g, 0x6a1d0c00 + pass);
      const long np = 4000;
      std::vector<double> x(2 * np), l(2 * np);
      double lmax = 0;
      for (long p = 0; p < np; ++p) {
        sample.draw(x[2 * p], x[2 * p + 1], l[2 * p], l[2 * p + 1], true, 0.5 * h0);
        for (int a = 0; a < 2; ++a) {
          if (small) l[2 * p + a] *= 0.3;
          lmax = std::max(lmax, l[2 * p + a]);
        }
      }
      const double reach = g.liveReachFor(lmax);
      EXPECT_TRUE(reach >= lmax && (reach == h0 || reach < 2 * lmax)) << reach << " " << lmax;
      g.markLiveCracks(sc.cracks, reach);
      marked[small] +=
          std::count_if(g.liveSlot.begin(), g.liveSlot.end(), [](PetscInt v) { return v >= 0; });
      Stencils rows, compact;
      ASSERT_TRUE(g.buildStencils(np, x.data(), l.data(), rows, false));
      ASSERT_TRUE(g.buildStencils(np, x.data(), l.data(), compact, true, true));
      // The reference: every entry of a cracked node (reached or reserved) whose segment from
      // the particle crosses the crack moves to the node's second slot.
      for (long p = 0; p < np; ++p)
        for (PetscInt e = rows.start[p]; e < rows.start[p + 1]; ++e) {
          const PetscInt n = rows.node[e];
          if (g.crackSlot[n] >= 0 &&
              gimp::cracks::crossing(sc.cracks[0], x[2 * p], x[2 * p + 1], g.X[n], g.Y[n]) != 0)
            rows.node[e] = g.crackSlot[n];
        }
      gimp::cracks::assignFields<2>(g, sc.cracks, np, x.data(), compact);
      const auto r = entriesOf(rows, np), b = entriesOf(compact, np);
      for (long p = 0; p < np; ++p) {
        const auto where = [&] {
          return lay.name + (grown ? " grown: " : ": ") +
                 at({{"xp", x[2 * p]}, {"yp", x[2 * p + 1]}});
        };
        const bool block = compact.isBlock(p) || compact.isBlock4(p);
        blocks += block;
        bool reserve = false, second = false;
        for (const auto &[slot, e] : r[p]) {
          second = second || slot >= g.nWindow;
          reserve = reserve || (slot < g.nWindow && g.crackSlot[slot] >= 0);
        }
        readdressed += second;
        blocksBesideReserve += block && reserve;
        compareEntries(r[p], b[p], h0, where, weight, gradient);
        ++compared;
      }
    }
  }
  std::printf("  particles %ld: blocks %ld (%ld beside a reserved node the crack does not reach), "
              "with a second field %ld; nodes marked %ld (full-size particles), %ld (0.3 times)\n",
              compared, blocks, blocksBesideReserve, readdressed, marked[0], marked[1]);
  EXPECT_LT(marked[1], marked[0]); // a smaller reach marks fewer nodes
  EXPECT_WORST_LE(weight, 1e-14);
  EXPECT_WORST_LE(gradient, 1e-12);
  EXPECT_GT(blocks, compared / 20);
  EXPECT_GT(blocksBesideReserve, compared / 50);
  EXPECT_GT(readdressed, compared / 50);
}

/// Contact's release on grid g (setup done with a release time tr of an increment grown at t0),
/// the two fields of every cracked node moving apart (masses 1 and 2, faces far apart: no contact,
/// the release alone acts): at (t - t0) / tr = 0, 0.25, 1 and 1.5 the nodes `newlyCut` names keep
/// the fields' relative velocity by that fraction (at most 1), in full and with the nodal momentum
/// kept, the accelerations changed by the velocities' change / dt; every other node is untouched.
/// Counts the nodes of each kind into bonded and free.
template <int D>
void expectRelease(const Grid<D> &g, gimp::cracks::Contact<D> &contact, double t0, double tr,
                   const std::function<bool(PetscInt)> &newlyCut, int &bonded, int &free) {
  const double dt = 1e-7;
  const size_t nv = D * static_cast<size_t>(g.nSlots);
  std::vector<double> mass(nv, 0.0), face(nv, 0.0), v0(nv, 0.0);
  for (PetscInt s = g.nWindow; s < g.nSlots; ++s) {
    const PetscInt n = g.slotNode[s];
    mass[D * n] = 1.0, mass[D * s] = 2.0;
    face[D * s] = 1.0;
    for (int q = 0; q < D; ++q)
      v0[D * n + q] = 0.3 - 1.3 * q, v0[D * s + q] = -0.6 + 1.1 * q;
  }
  bonded = free = 0;
  for (const double frac : {0.0, 0.25, 1.0, 1.5}) {
    std::vector<double> v = v0, a(nv, 0.0);
    contact.apply(g, 0.0, dt, mass.data(), face.data(), v.data(), a.data(), t0 + frac * tr);
    for (PetscInt s = g.nWindow; s < g.nSlots; ++s) {
      const PetscInt n = g.slotNode[s];
      const bool cut = newlyCut(n);
      if (frac == 0.0) ++(cut ? bonded : free);
      const double keep = cut ? std::min(frac, 1.0) : 1.0;
      for (int q = 0; q < D; ++q) {
        const double rel0 = v0[D * n + q] - v0[D * s + q], rel = v[D * n + q] - v[D * s + q];
        EXPECT_NEAR(rel, keep * rel0, 1e-15) << "node " << n << " at " << frac;
        EXPECT_NEAR(v[D * n + q] + 2.0 * v[D * s + q], v0[D * n + q] + 2.0 * v0[D * s + q], 1e-15);
        EXPECT_NEAR(a[D * n + q] * dt, v[D * n + q] - v0[D * n + q], 1e-15);
        EXPECT_NEAR(a[D * s + q] * dt, v[D * s + q] - v0[D * s + q], 1e-15);
      }
    }
  }
}

TEST(CrackContact, ReleaseBondsTheNewlyCutNodes) {
  // A crack along y = 8 h grown by one cell from x = 8 h to 9 h at t0, released over tr: the
  // cracked nodes whose nearest crack point lies on the increment (x >= 8 h here: the node at the
  // old tip was not cut before) are bonded (expectRelease).
  const double h = 1e-3, t0 = 2e-3, tr = 1e-3;
  const gimp::Scene<2> sc = gimp::test::plainScene({0, 0, 16 * h, 16 * h}, h, {});
  gimp::Crack c;
  c.points = {{-0.3 * h, 8 * h}, {8 * h, 8 * h}, {9 * h, 8 * h}};
  Grid<2> g;
  g.crackReserve.push_back({8 * h, 8 * h, 3 * h}); // (where it may grow: nodes ahead have slots)
  ASSERT_EQ(static_cast<int>(g.create(PETSC_COMM_SELF, h, sc.levelBoxes(), {c})), 0);
  const gimp::cracks::Release<2> grown{{8 * h, 8 * h}, {9 * h, 8 * h}, t0};
  int bonded = 0, free = 0;
  for (const double release : {tr, 0.0}) { // (without a release time nothing is bonded)
    gimp::cracks::Contact<2> contact;
    contact.setup(g, {c}, {grown}, release);
    expectRelease<2>(
        g, contact, t0, tr, [&](PetscInt n) { return release > 0 && g.X[n] >= 8 * h - 1e-12 * h; },
        bonded, free);
    if (release > 0) {
      EXPECT_GT(bonded, 4);
    }
    EXPECT_GT(free, 4);
  }
}

TEST(CrackContact, ReleaseBondsTheNewlyCutNodes3D) {
  // A crack in the plane z = 8 h whose front x = 8 h advanced at t0 by one cell for y <= 8 h and
  // by two beyond, released over tr: the cracked nodes whose nearest point on the crack is not
  // behind the front before (x >= 8 h here, the nodes on that front included) are bonded
  // (expectRelease); for an advance of another crack, none.
  const double h = 1e-3, t0 = 2e-3, tr = 1e-3, up[3] = {0, 0, 1};
  gimp::Scene<3> sc;
  sc.h = h;
  sc.domain = {0, 0, 0, 16 * h, 16 * h, 16 * h};
  sc.levels.assign(1, gimp::LevelBox<3>{sc.domain, 1});
  const auto plane = [&](const std::vector<std::array<double, 2>> &xy) {
    std::vector<std::array<double, 3>> p;
    for (const auto &q : xy)
      p.push_back({q[0], q[1], 8 * h});
    return gimp::cracks::makeSurface(p, up);
  };
  const double lo = -0.3 * h, hi = 16.3 * h;
  gimp::CrackSurface before = plane({{lo, lo}, {8 * h, lo}, {8 * h, hi}, {lo, hi}});
  before.front = {0, 1, 0, 0};
  gimp::CrackSurface c =
      plane({{lo, lo}, {9 * h, lo}, {9 * h, 8 * h}, {10 * h, 8 * h}, {10 * h, hi}, {lo, hi}});
  c.front = {0, 1, 1, 1, 0, 0};
  Grid<3> g;
  g.crackReserveSurfaces.push_back(plane({{8 * h, lo}, {12 * h, lo}, {12 * h, hi}, {8 * h, hi}}));
  ASSERT_EQ(static_cast<int>(g.create(PETSC_COMM_SELF, h, sc.levelBoxes(), {c})), 0);
  for (const int other : {0, 1}) {
    gimp::cracks::Contact<3> contact;
    contact.setup(g, {c}, {gimp::cracks::Release<3>{other, before, t0}}, tr);
    int bonded = 0, free = 0;
    expectRelease<3>(
        g, contact, t0, tr, [&](PetscInt n) { return !other && g.X[n] >= 8 * h - 1e-12 * h; },
        bonded, free);
    if (!other) {
      EXPECT_GT(bonded, 16);
    }
    EXPECT_GT(free, 16);
  }
}

TEST(GridStencils, CrackedNodesServeParticlesUpToH0) {
  // A particle of half-size up to h0 (the largest a run accepts) whose segment from its centre to
  // a node of its stencil crosses the crack must find that node with a second field, marked live
  // for its size: its centre may lie sqrt(2) h0 from the node's support, beyond the crack's
  // Euclidean reach of h0 that findCrackedNodes used before (near the support's corners).
  long crossings = 0, missed = 0, particles = 0;
  for (const Layout &lay : twoLevelLayouts()) {
    gimp::Scene<2> sc = sceneOf(lay);
    const BoxOf<2> D = sc.levelBoxes()[0].box;
    const double h0 = sc.h, W = D[2] - D[0], H = D[3] - D[1];
    gimp::Crack c; // kinked, its segments at angles to the grid lines
    c.points = {{D[0] - 0.3 * h0, D[1] + 0.52 * H},
                {D[0] + 0.31 * W, D[1] + 0.43 * H},
                {D[0] + 0.47 * W, D[1] + 0.61 * H}};
    sc.cracks = {c};
    Grid<2> g;
    ASSERT_EQ(static_cast<int>(g.create(PETSC_COMM_SELF, h0, sc.levelBoxes(), sc.cracks)), 0);
    std::mt19937_64 rng(0x6a1dc0de);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    const long np = 4000;
    std::vector<double> x(2 * np), l(2 * np);
    double lmax = 0;
    for (long p = 0; p < np; ++p) // within 2 h0 of the crack's first two segments
      for (;;) {
        const double t = uni(rng), s = 4 * uni(rng) - 2;
        const auto &a = c.points[t < 0.5 ? 0 : 1], &b = c.points[t < 0.5 ? 1 : 2];
        const double u = t < 0.5 ? 2 * t : 2 * t - 1, dx = b[0] - a[0], dy = b[1] - a[1],
                     len = std::hypot(dx, dy);
        x[2 * p] = a[0] + u * dx - s * h0 * dy / len;
        x[2 * p + 1] = a[1] + u * dy + s * h0 * dx / len;
        for (int k = 0; k < 2; ++k) {
          l[2 * p + k] = h0 * (0.55 + 0.449 * uni(rng));
          lmax = std::max(lmax, l[2 * p + k]);
        }
        if (x[2 * p] - l[2 * p] > D[0] && x[2 * p] + l[2 * p] < D[2] &&
            x[2 * p + 1] - l[2 * p + 1] > D[1] && x[2 * p + 1] + l[2 * p + 1] < D[3])
          break;
      }
    g.markLiveCracks(sc.cracks, g.liveReachFor(lmax));
    Stencils rows;
    ASSERT_TRUE(g.buildStencils(np, x.data(), l.data(), rows, false));
    for (long p = 0; p < np; ++p, ++particles)
      for (PetscInt e = rows.start[p]; e < rows.start[p + 1]; ++e) {
        const PetscInt n = rows.node[e];
        if (gimp::cracks::crossing(c, x[2 * p], x[2 * p + 1], g.X[n], g.Y[n]) == 0) continue;
        ++crossings;
        missed += g.crackSlot[n] < 0 || g.liveSlot[n] < 0;
      }
  }
  std::printf("  particles %ld: segments across the crack %ld, to a node without a live second "
              "field %ld\n",
              particles, crossings, missed);
  EXPECT_GT(crossings, particles);
  EXPECT_EQ(missed, 0);
}

// ---------------------------------------------------------------------------------------------
// 2. Point shape functions: S_i(x, y) = tent(x - X_i; Lx-, Lx+) tent(y - Y_i; Ly-, Ly+) summed
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
    const Grid<2> &g = *gp;
    const double h0 = g.h0();
    const BoxOf<2> &D = g.levels[0].box;
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

} // namespace
