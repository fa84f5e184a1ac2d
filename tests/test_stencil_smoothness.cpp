// Unit tests of the smoothness of the GIMP stencils on the composite grid in
// include/gimp/grid/grid.hpp (paper section 3), on the refined layouts of grid_layouts.hpp.
// (Their values and identities: test_stencils.cpp.)
//
//   1. The gradient is the derivative of the weight: central differences, node by node.
//   2. C1 continuity at transition nodes: no jump of weight or gradient along lines that cross
//      a coarse-fine interface next to hanging nodes.
//
// All random sampling uses a fixed-seed std::mt19937_64, so every run checks the same points.
// Random checks keep the largest error and report where (layout and particle) it occurred.
#include "gimp/grid/grid.hpp"

#include "grid_layouts.hpp"
#include "test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace {

using gimp::test::at;
using gimp::test::Worst;

using gimp::test::insideDomain;
using gimp::test::Layout;
using gimp::test::makeGrid;
using gimp::test::Sampler;
using gimp::test::sceneOf;
using gimp::test::threeLevelLayouts;
using gimp::test::twoLevelLayouts;

using gimp::BoxOf;
using gimp::Grid;
using Stencils = gimp::Stencils<2>;

// ---------------------------------------------------------------------------------------------
// 1. The gradient is the derivative of the weight: move the particle by +-eps in x and in y,
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
    const Grid<2> &g = *gp;
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
      // so skip those few particles (continuity there is test 2).
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
// 2. C1 continuity at transition nodes (paper Figs. 3 and 4(b)). A particle moves along a line
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
    const Grid<2> &g = *gp;
    const double h0 = g.h0(), hmin = g.hMin(), delta = 1e-9 * hmin;
    const BoxOf<2> &D = g.levels[0].box;
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

} // namespace
