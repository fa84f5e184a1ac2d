// Internal-force patch test on composite grids of three levels (paper section 3).
//
// A rectangular block B is tiled by particles: every leaf cell of the grid inside B is split
// into n x n particles of that cell's size (so the particles are smaller where the grid is
// finer). Every particle carries the same Cauchy stress sigma. The nodal internal forces are
//
//     f_i = - sum_p V_p sigma . grad w_ip,
//
// with the particles' GIMP stencils from Grid::buildStencils and the solver's internal-force
// kernel transfer::internalForce (node weight w_x w_y, gradient (g_x w_y, w_x g_y)). Since the GIMP
// weight is the average of the node's point shape function S_i (a product of tents with the node's
// influence zones) over the particle, V_p grad w_ip is the integral of grad S_i over the particle,
// and for particles that tile B
//
//     f_i = - integral_B sigma . grad S_i = - boundary integral of S_i sigma . n.
//
// So the test asserts, for each layout:
//   1. interior nodes (S_i zero on and outside the boundary of B) carry no force:
//      |f_i| <= 1e-10 max |f| over the other nodes;
//   2. the forces sum to zero (partition of unity: sum_i grad w_ip = 0 for each particle);
//   3. every node's force equals the exact boundary integral above, computed independently from
//      the node's position and zones (tents integrated along the four edges of B);
//   4. per edge side: the forces of the nodes whose shape function reaches that edge add up to
//      the traction resultant -sigma . n |edge|. Corner nodes also collect load from the
//      adjacent edges, so this is checked on the stress components that load only the edge in
//      question: sxx alone for the left and right edges, syy alone for the bottom and top
//      edges, and the tangential component of sxy alone for all four;
//   5. the node shape functions restricted to each edge form a partition of unity there (the
//      exact edge integrals of item 3 add up to the edge length).
//
// Layouts: level 2 inside level 1 in the middle, on level 1's edge and in its corner, on the
// domain edge with the block at the domain corner, a one-cell strip, level 2 coinciding with
// level 1, and the block's edges along level boundaries; ratios 2, 3 and 4 (also mixed); n = 1,
// 2 and 3 particles per cell side. Each layout is tested twice: with B on level-0 grid lines,
// and with the same particles translated by a fraction of a level-0 cell in x and y, so that
// particles straddle level boundaries and level-0 particles lie inside fine levels (as when a
// body drifts across the grid; the identities above hold for any tiling).
#include "gimp/grid/grid.hpp"
#include "gimp/grid/shape.hpp"
#include "gimp/input/scene.hpp"
#include "gimp/transfer/internal_force.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

using gimp::BoxOf;
using gimp::Grid;
using gimp::Level;
using gimp::LevelBox;
using gimp::Scene;
using Stencils = gimp::Stencils<2>;
using gimp::shape::tent;
using gimp::shape::tentIntegral;

// Domain origin and level-0 cell size that are not binary fractions, so that node and particle
// coordinates carry round-off as in real scenes.
constexpr double kX0 = -1.3, kY0 = 0.7, kH0 = 0.37;
constexpr double kTol = 1e-10;

/// A box in level-0 cells from the domain origin (fractions where it lies on finer grid lines).
struct CellBox {
  double i0, j0, i1, j1;
};

struct PatchLayout {
  std::string name;
  int nx, ny;                                // level-0 cells of the domain
  std::vector<std::pair<CellBox, int>> fine; // level boxes and their ratios
  CellBox block;                             // the tiled block, on level-0 grid lines
};

BoxOf<2> toBox(const CellBox &b) {
  return {kX0 + b.i0 * kH0, kY0 + b.j0 * kH0, kX0 + b.i1 * kH0, kY0 + b.j1 * kH0};
}

Scene<2> sceneOf(const PatchLayout &lay) {
  Scene<2> sc;
  sc.h = kH0;
  sc.domain = {kX0, kY0, kX0 + lay.nx * kH0, kY0 + lay.ny * kH0};
  sc.levels.assign(1, LevelBox<2>{sc.domain, 1});
  for (const auto &[b, r] : lay.fine)
    sc.levels.push_back(LevelBox<2>{toBox(b), r});
  return sc;
}

/// Three-level layouts for ratios (r1, r2); f = one level-1 cell in level-0 cells.
std::vector<PatchLayout> layouts() {
  std::vector<PatchLayout> v;
  const std::pair<int, int> ratios[] = {{2, 2}, {3, 3}, {4, 4}, {2, 4}, {4, 2}, {3, 2}};
  for (const auto &[r1, r2] : ratios) {
    const double f = 1.0 / r1;
    const std::string s = " r=" + std::to_string(r1) + "," + std::to_string(r2);
    const CellBox L1 = {4, 3, 12, 9}; // level 1 in most layouts
    // Level 2 inside the block, level 1 cut by the block's right and top edges.
    v.push_back({"middle" + s, 14, 12, {{L1, r1}, {{6 + f, 4, 8, 7 - f}, r2}}, {1, 1, 9, 8}});
    // The block's right edge cuts level 2: boundary nodes and small particles on all levels.
    v.push_back(
        {"edge in level 2" + s, 14, 12, {{L1, r1}, {{6 + f, 4, 8, 7 - f}, r2}}, {1, 1, 7, 8}});
    // Level 2 on level 1's left and bottom edges (its corner is level 1's corner).
    v.push_back({"parent corner" + s, 14, 12, {{L1, r1}, {{4, 3, 7 + f, 6}, r2}}, {1, 1, 9, 8}});
    // Level 2 on level 1's top edge; the block's top edge runs along both.
    v.push_back({"parent edge" + s, 14, 12, {{L1, r1}, {{6, 6, 8 + f, 9}, r2}}, {1, 1, 10, 9}});
    // All three levels share the domain corner; so does the block.
    v.push_back(
        {"domain corner" + s, 14, 12, {{{0, 0, 7, 6}, r1}, {{0, 0, 3, 3 - f}, r2}}, {0, 0, 9, 8}});
    // A one-cell strip of level 2 across level 1 from its bottom to its top edge.
    v.push_back({"strip" + s, 14, 12, {{L1, r1}, {{7, 3, 7 + f, 9}, r2}}, {1, 2, 10, 8}});
    // Level 2 coincides with level 1: level-2 cells next to level-0 cells.
    v.push_back(
        {"coincident" + s, 14, 12, {{{5, 4, 10, 8}, r1}, {{5, 4, 10, 8}, r2}}, {1, 1, 8, 7}});
    // The block's left and bottom edges run along level 1's boundary.
    v.push_back(
        {"block on interface" + s, 14, 12, {{L1, r1}, {{6, 4 + f, 9, 7}, r2}}, {4, 3, 11, 11}});
  }
  return v;
}

struct Particles {
  std::vector<double> x, l, V; // centres [2], half-sizes [2], volumes
  PetscInt size() const { return static_cast<PetscInt>(V.size()); }
};

/// Every leaf cell inside the block split into n x n particles of its size, then translated by
/// (sx, sy). The block lies on level-0 grid lines, so its leaf cells tile it.
Particles tile(const Grid<2> &g, const CellBox &blk, int n, double sx, double sy) {
  Particles p;
  const std::int64_t total = g.levels[0].step; // finest-lattice units per level-0 cell
  const auto lat = [&](double c) { return static_cast<std::int64_t>(std::llround(c * total)); };
  const std::int64_t bu0 = g.levels[0].lo[0] + lat(blk.i0), bu1 = g.levels[0].lo[0] + lat(blk.i1);
  const std::int64_t bv0 = g.levels[0].lo[1] + lat(blk.j0), bv1 = g.levels[0].lo[1] + lat(blk.j1);
  for (int q = 0; q < static_cast<int>(g.levels.size()); ++q) {
    const Level<2> &L = g.levels[q];
    for (PetscInt j = 0; j + 1 < L.n[1]; ++j)
      for (PetscInt i = 0; i + 1 < L.n[0]; ++i) {
        const std::int64_t u = L.lo[0] + i * L.step, v = L.lo[1] + j * L.step;
        if (u < bu0 || u + L.step > bu1 || v < bv0 || v + L.step > bv1) continue;
        if (g.leafLevelAtDoubled(2 * u + L.step, 2 * v + L.step) != q) continue;
        const double cx = g.origin[0] + static_cast<double>(u) * g.unit;
        const double cy = g.origin[1] + static_cast<double>(v) * g.unit;
        const double d = L.h / n;
        for (int b = 0; b < n; ++b)
          for (int a = 0; a < n; ++a) {
            p.x.push_back(cx + (a + 0.5) * d + sx);
            p.x.push_back(cy + (b + 0.5) * d + sy);
            p.l.push_back(0.5 * d);
            p.l.push_back(0.5 * d);
            p.V.push_back(d * d);
          }
      }
  }
  return p;
}

/// f_i = - sum_p V_p sigma . grad w_ip for sigma = (sxx, syy, sxy), 2 per window node: the
/// solver's own internal-force kernel (transfer::internalForce) on these particles.
std::vector<double> internalForces(const Grid<2> &g, const Particles &p, const Stencils &s,
                                   const std::array<double, 3> &sig) {
  std::vector<double> f(2 * static_cast<size_t>(g.nWindow), 0.0);
  const std::vector<double> stress = [&] {
    std::vector<double> t(3 * static_cast<size_t>(p.size())); // (xx, yy, xy: the stored order)
    for (PetscInt k = 0; k < p.size(); ++k)
      for (int c = 0; c < 3; ++c)
        t[3 * k + c] = sig[c];
    return t;
  }();
  gimp::transfer::internalForce<2>(s, p.size(), p.V.data(), stress.data(), f.data());
  return f;
}

// Block edges: 0 left (x = a), 1 right (x = b), 2 bottom (y = c), 3 top (y = d).
constexpr double kNormal[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
const char *const kSide[4] = {"left", "right", "bottom", "top"};

/// Integral of node n's point shape function along each edge of the block [a, b] x [c, d].
std::array<double, 4> edgeIntegrals(const Grid<2> &g, PetscInt n, const BoxOf<2> &B) {
  const double X = g.X[n], Y = g.Y[n];
  const double *z = &g.zone[4 * n];
  const double alongY = tentIntegral(B[1] - Y, B[3] - Y, z[2], z[3]);
  const double alongX = tentIntegral(B[0] - X, B[2] - X, z[0], z[1]);
  return {tent(B[0] - X, z[0], z[1]) * alongY, tent(B[2] - X, z[0], z[1]) * alongY,
          tent(B[1] - Y, z[2], z[3]) * alongX, tent(B[3] - Y, z[2], z[3]) * alongX};
}

/// The node's shape function vanishes on the boundary of B and outside it: its support lies in
/// B, and a zero zone (domain edge) does not sit on an edge of B.
bool interior(const Grid<2> &g, PetscInt n, const BoxOf<2> &B) {
  const double tol = 1e-9 * g.hMin();
  const double X = g.X[n], Y = g.Y[n];
  const double *z = &g.zone[4 * n];
  auto in1d = [tol](double c, double Lm, double Lp, double a, double b) {
    return c - Lm >= a - tol && c + Lp <= b + tol && !(Lm == 0.0 && std::abs(c - a) < tol) &&
           !(Lp == 0.0 && std::abs(c - b) < tol);
  };
  return in1d(X, z[0], z[1], B[0], B[2]) && in1d(Y, z[2], z[3], B[1], B[3]);
}

struct CaseResult {
  double interior = 0, sum = 0, node = 0, side = 0, unity = 0; // relative errors
  long particles = 0, interiorNodes = 0, interiorTransition = 0, boundaryNodes = 0;
  std::array<long, 3> interiorPerLevel{};
  std::string where;     // worst node of the interior check
  std::string sideWhere; // worst edge of the per-side check
};

int levelOf(const Grid<2> &g, PetscInt n) {
  int k = 0;
  while (k + 1 < static_cast<int>(g.levels.size()) && n >= g.levels[k + 1].offset)
    ++k;
  return k;
}

/// The five identities of the file comment on one tiling of one layout, with the worst error of
/// each. One function on purpose (longer than 80 lines): the identities share the forces, the
/// node classification and the exact edge integrals computed once at its start, and read best
/// in the order the file comment lists them.
CaseResult runCase(const Grid<2> &g, const PatchLayout &lay, int n, bool shifted) {
  CaseResult r;
  const double sx = shifted ? 0.4137 * kH0 : 0.0, sy = shifted ? 0.2719 * kH0 : 0.0;
  const Particles p = tile(g, lay.block, n, sx, sy);
  BoxOf<2> B = toBox(lay.block);
  B[0] += sx;
  B[2] += sx;
  B[1] += sy;
  B[3] += sy;
  Stencils s;
  g.buildStencils(p.size(), p.x.data(), p.l.data(), s);
  r.particles = p.size();
  double area = 0;
  for (double v : p.V)
    area += v;
  EXPECT_NEAR(area, (B[2] - B[0]) * (B[3] - B[1]), 1e-12 * area) << lay.name << ": tiling";

  const std::array<double, 3> sigma = {3.0, -1.0, 0.5};
  const std::vector<double> f = internalForces(g, p, s, sigma);
  std::vector<std::array<double, 4>> I(g.nWindow);
  std::vector<char> in(g.nWindow, 0);
  double maxB = 0;
  for (PetscInt i = 0; i < g.nWindow; ++i) {
    if (!g.active[i]) continue;
    I[i] = edgeIntegrals(g, i, B);
    in[i] = interior(g, i, B);
    if (!in[i]) {
      maxB = std::max(maxB, std::hypot(f[2 * i], f[2 * i + 1]));
      if (f[2 * i] != 0.0 || f[2 * i + 1] != 0.0) ++r.boundaryNodes;
    } else {
      ++r.interiorNodes;
      ++r.interiorPerLevel[levelOf(g, i)];
      r.interiorTransition += !g.regular[i];
    }
  }
  EXPECT_GT(maxB, 0.0) << lay.name;

  // 1-3: interior forces, total, and every node against the exact boundary integral.
  double sum[2] = {0, 0}, worstInterior = 0;
  for (PetscInt i = 0; i < g.nWindow; ++i) {
    if (!g.active[i]) continue;
    const double fx = f[2 * i], fy = f[2 * i + 1];
    sum[0] += fx;
    sum[1] += fy;
    double ex = 0, ey = 0; // - sum_e sigma . n_e * integral_e S_i
    for (int e = 0; e < 4; ++e) {
      const double nx = kNormal[e][0], ny = kNormal[e][1];
      ex -= (sigma[0] * nx + sigma[2] * ny) * I[i][e];
      ey -= (sigma[2] * nx + sigma[1] * ny) * I[i][e];
    }
    r.node = std::max(r.node, std::hypot(fx - ex, fy - ey) / maxB);
    if (in[i]) {
      const double m = std::hypot(fx, fy) / maxB;
      if (!(m <= worstInterior)) {
        worstInterior = m;
        std::ostringstream w;
        w.precision(10);
        w << "level " << levelOf(g, i) << " node (" << g.X[i] << ", " << g.Y[i] << ") zones ["
          << g.zone[4 * i] << ", " << g.zone[4 * i + 1] << ", " << g.zone[4 * i + 2] << ", "
          << g.zone[4 * i + 3] << "] f = (" << fx << ", " << fy << ")";
        r.where = w.str();
      }
    }
  }
  r.interior = worstInterior;
  r.sum = std::hypot(sum[0], sum[1]) / maxB;

  // 4-5: per edge side, with stress states that load only that edge in the checked component.
  const double len[4] = {B[3] - B[1], B[3] - B[1], B[2] - B[0], B[2] - B[0]};
  for (int e = 0; e < 4; ++e) {
    double unity = 0;
    for (PetscInt i = 0; i < g.nWindow; ++i)
      if (g.active[i]) unity += I[i][e];
    r.unity = std::max(r.unity, std::abs(unity / len[e] - 1.0));
  }
  const std::array<double, 3> states[3] = {{sigma[0], 0, 0}, {0, sigma[1], 0}, {0, 0, sigma[2]}};
  for (const auto &st : states) {
    const std::vector<double> fs = internalForces(g, p, s, st);
    double scale = 0;
    for (PetscInt i = 0; i < g.nWindow; ++i)
      scale = std::max(scale, std::hypot(fs[2 * i], fs[2 * i + 1]));
    for (int e = 0; e < 4; ++e) {
      // Traction resultant of this edge, and of its two neighbours.
      auto resultant = [&](int q, int c) {
        const double nx = kNormal[q][0], ny = kNormal[q][1];
        return -(c == 0 ? st[0] * nx + st[2] * ny : st[2] * nx + st[1] * ny) * len[q];
      };
      const int adj[2] = {e < 2 ? 2 : 0, e < 2 ? 3 : 1};
      double tot[2] = {0, 0};
      for (PetscInt i = 0; i < g.nWindow; ++i)
        if (g.active[i] && I[i][e] != 0.0) {
          tot[0] += fs[2 * i];
          tot[1] += fs[2 * i + 1];
        }
      for (int c = 0; c < 2; ++c) {
        if (resultant(adj[0], c) != 0.0 || resultant(adj[1], c) != 0.0) continue;
        const double err = std::abs(tot[c] - resultant(e, c)) / scale;
        if (!(err <= r.side)) {
          r.side = err;
          std::ostringstream w;
          w.precision(12);
          w << kSide[e] << " edge, component " << c << " (stress " << st[0] << ", " << st[1] << ", "
            << st[2] << "): sum " << tot[c] << ", traction resultant " << resultant(e, c);
          r.sideWhere = w.str();
        }
      }
    }
  }
  return r;
}

TEST(PatchLevels, InternalForcesOnThreeLevels) {
  double worst[5] = {0, 0, 0, 0, 0};
  long cases = 0;
  std::printf("  %-30s %2s %5s %8s %8s %5s %6s %9s %9s %9s %9s %9s\n", "layout", "n", "shift",
              "particles", "interior", "trans.", "boundary", "interior", "sum", "node", "side",
              "unity");
  for (const PatchLayout &lay : layouts()) {
    Grid<2> g;
    ASSERT_EQ(static_cast<int>(g.create(PETSC_COMM_SELF, kH0, sceneOf(lay).levelBoxes())), 0)
        << lay.name;
    ASSERT_EQ(g.levels.size(), 3u);
    for (int n : {1, 2, 3})
      for (bool shifted : {false, true}) {
        const CaseResult r = runCase(g, lay, n, shifted);
        const std::string name = lay.name + " n=" + std::to_string(n) + (shifted ? " shifted" : "");
        std::printf("  %-30s %2d %5s %8ld %8ld %5ld %6ld %9.2e %9.2e %9.2e %9.2e %9.2e\n",
                    lay.name.c_str(), n, shifted ? "yes" : "no", r.particles, r.interiorNodes,
                    r.interiorTransition, r.boundaryNodes, r.interior, r.sum, r.node, r.side,
                    r.unity);
        // The block reaches into every level and has interior nodes on each (level 1 has
        // none where level 2 covers it).
        for (int k = 0; k < 3; ++k)
          if (g.activeNodes(k) > 0) {
            EXPECT_GT(r.interiorPerLevel[k], 0) << name << ": no interior node on level " << k;
          }
        EXPECT_GT(r.interiorTransition, 0) << name << ": no interior transition node";
        EXPECT_LE(r.interior, kTol) << name << ": interior force, worst at " << r.where;
        EXPECT_LE(r.sum, kTol) << name << ": sum of the forces";
        EXPECT_LE(r.node, kTol) << name << ": nodal force against the boundary integral";
        EXPECT_LE(r.side, kTol) << name << ": per-side resultant, worst at " << r.sideWhere;
        EXPECT_LE(r.unity, kTol) << name << ": edge partition of unity";
        const double e[5] = {r.interior, r.sum, r.node, r.side, r.unity};
        for (int q = 0; q < 5; ++q)
          worst[q] = std::max(worst[q], e[q]);
        ++cases;
      }
  }
  std::printf("  %ld cases; worst relative errors: interior %.2e, sum %.2e, node %.2e, side "
              "%.2e, edge unity %.2e (tolerance %.0e)\n",
              cases, worst[0], worst[1], worst[2], worst[3], worst[4], kTol);
}

} // namespace
