// Unit tests of the external forces in include/gimp/physics/boundary.hpp (Eqs. 8 and 9) on a
// three-level composite grid.
//
// A rectangular body B is tiled by particles as in test_patch_levels: every leaf cell inside B
// split into n x n particles of its size; once with B on grid lines and once translated by a
// fraction of a level-0 cell, so that particles straddle level borders. B's right and top
// edges cross all three levels.
//
//   1. Tractions (Eq. 8): with a traction vector on one side (and on all four), the nodal forces
//      add up to traction x side length x thickness, and reach nodes of every level the side
//      crosses. A dead load: stretching the particles along the side does not change it.
//   2. edgeShape: over the stencil of a particle, the node shape functions along an edge add up
//      to 1 (partition of unity along the edge), for edges on B's sides and through the centre.
//   3. Penalty (Eq. 9): a DisplacementBC on the left side with u_bar = 0 and the body displaced
//      by +delta in x gives the force -alpha delta |side| thickness on the body, plus
//      sigma n |side| thickness with the traction term on; a body stretched about the fixed
//      edge has no gap there and gets only the traction term. Both the nodal forces and the
//      recorded reactions are checked.
//   4. Boundary::setup: alpha from -gimp_penalty, its stability bounds, and the default choice.
//
// Tolerances: every resultant is a sum of per-particle partitions of unity along the edge
// (each good to ~1e-15) over a few hundred particles, relative to the resultant: 1e-12.
#include "gimp/physics/boundary.hpp"

#include "test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

namespace {

using gimp::BoxOf;
using gimp::DisplacementBC;
using gimp::Grid;
using gimp::InputError;
using gimp::Level;
using gimp::LevelBox;
using gimp::ParticleView;
using gimp::Scene;
using gimp::Side;
using gimp::Traction;
using Boundary = gimp::physics::Boundary<2>;
using gimp::test::at;
using gimp::test::Worst;
using Stencils = gimp::Stencils<2>;

constexpr double kX0 = -1.3, kY0 = 0.7, kH0 = 0.37;
constexpr double kThickness = 0.25;
const char *const kSideName[4] = {"left", "right", "bottom", "top"};

/// Grid: 14 x 12 level-0 cells; level 1 (ratio 2) over cells [4, 12] x [3, 9]; level 2
/// (ratio 4) over [6.5, 8.5] x [5, 8.5]. Body: cells [1, 8] x [2, 8], so its right side
/// crosses levels 0, 1 and 2 (x = 8), its top side too (y = 8), left and bottom lie on level 0.
Scene<2> scene() {
  Scene<2> sc;
  sc.h = kH0;
  sc.domain = {kX0, kY0, kX0 + 14 * kH0, kY0 + 12 * kH0};
  sc.levels.assign(1, LevelBox<2>{sc.domain, 1});
  sc.levels.push_back(
      LevelBox<2>{{kX0 + 4 * kH0, kY0 + 3 * kH0, kX0 + 12 * kH0, kY0 + 9 * kH0}, 2});
  sc.levels.push_back(
      LevelBox<2>{{kX0 + 6.5 * kH0, kY0 + 5 * kH0, kX0 + 8.5 * kH0, kY0 + 8.5 * kH0}, 4});
  gimp::Body<2> b;
  b.box = {kX0 + 1 * kH0, kY0 + 2 * kH0, kX0 + 8 * kH0, kY0 + 8 * kH0};
  sc.bodies.push_back(b);
  gimp::Material &m = sc.material;
  m.E = 1.0e6;
  m.nu = 0.3;
  m.rho = 1000.0;
  m.thickness = kThickness;
  m.mu = m.E / (2.0 * (1.0 + m.nu));
  m.lambda = m.E * m.nu / ((1.0 + m.nu) * (1.0 - 2.0 * m.nu));
  m.lambdaStar = m.lambda; // plane strain
  return sc;
}

/// Particle arrays owned by the test, and a ParticleView on them.
struct Particles {
  std::vector<double> x, X0, v, m, V0, V, l, l0, F, s, szz, eps;
  std::vector<PetscInt> trac, dbc;
  PetscInt n = 0;
  void add(double cx, double cy, double hx, double hy) {
    x.insert(x.end(), {cx, cy});
    X0.insert(X0.end(), {cx, cy});
    v.insert(v.end(), {0.0, 0.0});
    m.push_back(1000.0 * 4 * hx * hy * kThickness);
    V0.push_back(4 * hx * hy * kThickness);
    V.push_back(4 * hx * hy * kThickness);
    l.insert(l.end(), {hx, hy});
    l0.insert(l0.end(), {hx, hy});
    F.insert(F.end(), {1.0, 0.0, 0.0, 1.0});
    s.insert(s.end(), {0.0, 0.0, 0.0}); // (xx, yy, xy)
    szz.push_back(0.0);
    eps.insert(eps.end(), {0.0, 0.0});
    trac.insert(trac.end(), {-1, -1});
    dbc.insert(dbc.end(), {-1, -1});
    ++n;
  }
  ParticleView<2> view() {
    ParticleView<2> p;
    p.n = n;
    p.x = x.data();
    p.X0 = X0.data();
    p.v = v.data();
    p.m = m.data();
    p.V0 = V0.data();
    p.V = V.data();
    p.l = l.data();
    p.l0 = l0.data();
    p.F = F.data();
    p.s = s.data();
    p.szz = szz.data();
    p.eps = eps.data();
    p.trac = trac.data();
    p.dbc = dbc.data();
    return p;
  }
  /// Which sides of box B particle k's edges lie on: bit q for side q (left, right, bottom, top).
  int sidesOf(PetscInt k, const BoxOf<2> &B) const {
    const double tol = 1e-9 * kH0;
    int r = 0;
    if (std::abs(X0[2 * k] - l0[2 * k] - B[0]) < tol) r |= 1;
    if (std::abs(X0[2 * k] + l0[2 * k] - B[2]) < tol) r |= 2;
    if (std::abs(X0[2 * k + 1] - l0[2 * k + 1] - B[1]) < tol) r |= 4;
    if (std::abs(X0[2 * k + 1] + l0[2 * k + 1] - B[3]) < tol) r |= 8;
    return r;
  }
};

/// Leaf cells inside B (on level-0 grid lines) split into n x n particles, shifted by (sx, sy).
Particles tile(const Grid<2> &g, const BoxOf<2> &B, int n, double sx, double sy) {
  Particles p;
  const auto lat = [&](double c, double o) {
    return static_cast<std::int64_t>(std::llround((c - o) / g.unit));
  };
  const std::int64_t bu0 = lat(B[0], g.origin[0]), bu1 = lat(B[2], g.origin[0]);
  const std::int64_t bv0 = lat(B[1], g.origin[1]), bv1 = lat(B[3], g.origin[1]);
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
          for (int a = 0; a < n; ++a)
            p.add(cx + (a + 0.5) * d + sx, cy + (b + 0.5) * d + sy, 0.5 * d, 0.5 * d);
      }
  }
  return p;
}

BoxOf<2> shifted(BoxOf<2> B, double sx, double sy) {
  B[0] += sx;
  B[2] += sx;
  B[1] += sy;
  B[3] += sy;
  return B;
}

int levelOf(const Grid<2> &g, PetscInt nd) {
  int k = 0;
  while (k + 1 < static_cast<int>(g.levels.size()) && nd >= g.levels[k + 1].offset)
    ++k;
  return k;
}

Traction<2> traction(Side side, double tx, double ty) {
  Traction<2> t;
  t.body = 0;
  t.side = static_cast<int>(side);
  t.value = {tx, ty};
  return t;
}

// The layouts: n particles per leaf cell side, unshifted and shifted.
struct Case {
  int n;
  bool shift;
  double sx() const { return shift ? 0.4137 * kH0 : 0.0; }
  double sy() const { return shift ? 0.2719 * kH0 : 0.0; }
  std::string name() const {
    return "n=" + std::to_string(n) + (shift ? " shifted" : " on grid lines");
  }
};
const Case kCases[] = {{1, false}, {1, true}, {2, false}, {2, true}};

// ---------------------------------------------------------------------------------------------
// 1. Tractions.

TEST(Boundary, TractionResultants) {
  Scene<2> sc = scene();
  sc.tractions = {traction(Side::Left, -3.0e3, 1.1e3), traction(Side::Right, 2.5e3, -0.7e3),
                  traction(Side::Bottom, 0.4e3, -1.9e3), traction(Side::Top, -0.6e3, 2.2e3)};
  Grid<2> g;
  ASSERT_EQ(static_cast<int>(g.create(PETSC_COMM_SELF, sc.h, sc.levelBoxes(), sc.cracks)), 0);
  ASSERT_EQ(g.levels.size(), 3u);
  Boundary bd;
  ASSERT_NO_THROW(bd.setup(PETSC_COMM_SELF, sc, g, 1e-5));
  ASSERT_TRUE(bd.active());
  Worst worst;
  for (const Case &c : kCases) {
    const BoxOf<2> B = shifted(sc.bodies[0].box, c.sx(), c.sy());
    const double side[4] = {B[3] - B[1], B[3] - B[1], B[2] - B[0], B[2] - B[0]};
    for (bool stretched : {false, true})
      for (int which = 0; which <= 4; ++which) { // one side (0-3) or all four (4)
        Particles P = tile(g, sc.bodies[0].box, c.n, c.sx(), c.sy());
        long onSide = 0;
        for (PetscInt k = 0; k < P.n; ++k) {
          const int s = P.sidesOf(k, B);
          for (int q = 0; q < 4; ++q)
            if ((s >> q & 1) && (which == 4 || which == q)) {
              P.trac[2 * k + q / 2] = q;
              ++onSide;
            }
          // A dead load: the resultant uses the initial edge length, whatever l is now.
          if (stretched) {
            P.l[2 * k] *= 1.3;
            P.l[2 * k + 1] *= 0.8;
          }
        }
        ASSERT_GT(onSide, 0);
        ParticleView<2> p = P.view();
        Stencils st;
        ASSERT_TRUE(g.buildStencils(p.n, p.x, p.l, st));
        std::vector<double> fe(2 * g.nWindow, 0.0);
        bd.externalForces(sc, g, st, p, 0.0, fe.data());
        double sum[2] = {0, 0}, expect[2] = {0, 0}, scale = 0;
        std::set<int> levels;
        for (PetscInt i = 0; i < g.nWindow; ++i) {
          sum[0] += fe[2 * i];
          sum[1] += fe[2 * i + 1];
          if (fe[2 * i] != 0.0 || fe[2 * i + 1] != 0.0) levels.insert(levelOf(g, i));
        }
        for (int q = 0; q < 4; ++q)
          if (which == 4 || which == q) {
            const auto &t = sc.tractions[q].value;
            expect[0] += t[0] * side[q] * kThickness;
            expect[1] += t[1] * side[q] * kThickness;
            scale = std::max(scale, std::hypot(t[0], t[1]) * side[q] * kThickness);
          }
        const std::string what = c.name() + (stretched ? " stretched " : " ") +
                                 (which == 4 ? "all sides" : kSideName[which]);
        worst.update(std::hypot(sum[0] - expect[0], sum[1] - expect[1]) / scale,
                     [&] { return what; });
        // The right and top sides cross all three levels: their load reaches each.
        if (which == 1 || which == 3 || which == 4) {
          EXPECT_EQ(levels.size(), 3u) << what;
        }
      }
  }
  EXPECT_WORST_LE(worst, 1e-12);
}

// ---------------------------------------------------------------------------------------------
// 2. edgeShape.

TEST(Boundary, EdgeShapeIsAPartitionOfUnity) {
  const Scene<2> sc = scene();
  Grid<2> g;
  ASSERT_EQ(static_cast<int>(g.create(PETSC_COMM_SELF, sc.h, sc.levelBoxes(), sc.cracks)), 0);
  Worst onSide, centre;
  for (const Case &c : kCases) {
    Particles P = tile(g, sc.bodies[0].box, c.n, c.sx(), c.sy());
    const BoxOf<2> B = shifted(sc.bodies[0].box, c.sx(), c.sy());
    Stencils st;
    ASSERT_TRUE(g.buildStencils(P.n, P.x.data(), P.l.data(), st));
    long sides = 0;
    for (PetscInt k = 0; k < P.n; ++k) {
      const int s = P.sidesOf(k, B);
      sides += s != 0;
      for (int q = 0; q < 4; ++q) {
        const int a = q / 2;
        const double nrm = q % 2 ? 1.0 : -1.0;
        // Edges on a side of B, and (every particle) the particle's centre line normal to a.
        for (bool isSide : {true, false}) {
          if (isSide && !(s >> q & 1)) continue;
          const double edge = P.x[2 * k + a] + (isSide ? nrm * P.l[2 * k + a] : 0.0);
          double sum = 0;
          for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e)
            sum += gimp::physics::faceShape<2>(g, st, e, a, nrm, edge);
          (isSide ? onSide : centre).update(std::abs(sum - 1.0), [&] {
            return c.name() + " " + kSideName[q] + " " +
                   at({{"particle", double(k)}, {"x", P.x[2 * k]}, {"y", P.x[2 * k + 1]}});
          });
        }
      }
    }
    EXPECT_GT(sides, 40) << c.name();
  }
  // Tents at the edge (exact to an ulp, adding to 1 across) times the 1D weights along it:
  // one particle's weights add up to 1 only within ~2e-14 (quotients like
  // (ua - ub)(ua + ub) / (2 lambda) of differences of numbers near 1; see test_transfer).
  EXPECT_WORST_LE(onSide, 1e-13);
  EXPECT_WORST_LE(centre, 1e-13);
}

// ---------------------------------------------------------------------------------------------
// 3. Penalty.

struct PenaltyResult {
  double sum[2];      // nodal forces
  double reaction[2]; // recorded reaction of condition 0
  double gap;
};

/// The body's particles with the left side constrained (dbc index 0), displaced by delta in x,
/// or stretched in x by e about the left side; every particle carries the stress s.
PenaltyResult penalty(const Scene<2> &sc, const Grid<2> &g, Boundary &bd, const Case &c,
                      double delta, double e, const double stress[3]) {
  Particles P = tile(g, sc.bodies[0].box, c.n, c.sx(), c.sy());
  const double xl = sc.bodies[0].box[0] + c.sx(); // the fixed side's initial position
  long onSide = 0;
  for (PetscInt k = 0; k < P.n; ++k) {
    P.X0[2 * k] = P.x[2 * k];
    P.X0[2 * k + 1] = P.x[2 * k + 1];
    if (P.sidesOf(k, shifted(sc.bodies[0].box, c.sx(), c.sy())) & 1) {
      P.dbc[2 * k] = 0;
      ++onSide;
    }
    P.x[2 * k] = xl + (1.0 + e) * (P.X0[2 * k] - xl) + delta;
    P.F[4 * k] = 1.0 + e;
    P.l[2 * k] = (1.0 + e) * P.l0[2 * k];
    for (int c = 0; c < 3; ++c) // (xx, yy, xy: the stored order)
      P.s[3 * k + c] = stress[c];
  }
  EXPECT_GT(onSide, 0);
  ParticleView<2> p = P.view();
  Stencils st;
  EXPECT_TRUE(g.buildStencils(p.n, p.x, p.l, st));
  std::vector<double> fe(2 * g.nWindow, 0.0);
  bd.externalForces(sc, g, st, p, 0.0, fe.data());
  PenaltyResult r{{0, 0}, {0, 0}, 0};
  for (PetscInt i = 0; i < g.nWindow; ++i) {
    r.sum[0] += fe[2 * i];
    r.sum[1] += fe[2 * i + 1];
  }
  std::vector<double> force, gap;
  EXPECT_EQ(static_cast<int>(bd.reactions(PETSC_COMM_SELF, force, gap)), 0);
  EXPECT_EQ(force.size(), 2u);
  EXPECT_EQ(gap.size(), 1u);
  r.reaction[0] = force[0];
  r.reaction[1] = force[1];
  r.gap = gap[0];
  return r;
}

TEST(Boundary, PenaltyForce) {
  Scene<2> sc = scene();
  DisplacementBC<2> d;
  d.body = 0;
  d.side = static_cast<int>(Side::Left); // u_bar = 0 in both components (empty tables)
  sc.dbcs = {d};
  sc.penalty = 2.0e9; // [Pa/m], within the bounds for dt = 1e-5 (test 4)
  Grid<2> g;
  ASSERT_EQ(static_cast<int>(g.create(PETSC_COMM_SELF, sc.h, sc.levelBoxes(), sc.cracks)), 0);
  const double L = sc.bodies[0].box[3] - sc.bodies[0].box[1]; // the left side's length
  const double stress[3] = {-2.0e4, 7.0e3, 5.0e3};            // sxx, syy, sxy
  const double delta = 1.0e-3;
  Worst wForce, wReaction, wGap;
  for (bool tractionTerm : {false, true}) {
    sc.penaltyTraction = tractionTerm;
    Boundary bd;
    ASSERT_NO_THROW(bd.setup(PETSC_COMM_SELF, sc, g, 1e-5));
    ASSERT_EQ(bd.alpha(), sc.penalty);
    for (const Case &c : kCases)
      for (bool stretch : {false, true}) {
        // Displaced by delta: u = delta on the left side. Stretched by e = 1e-3 about the left
        // side: the edge does not move (u = x - X0 + (F - I) n l0 = e l0 - e l0 = 0).
        const PenaltyResult r =
            penalty(sc, g, bd, c, stretch ? 0.0 : delta, stretch ? 1.0e-3 : 0.0, stress);
        const double u = stretch ? 0.0 : delta;
        // Eq. 9 on the side n = (-1, 0): f = (sigma n - alpha u) |side| thickness.
        const double n = -1.0;
        const double ts = tractionTerm ? 1.0 : 0.0;
        const double ex = (ts * stress[0] * n - sc.penalty * u) * L * kThickness;
        const double ey = (ts * stress[2] * n) * L * kThickness;
        const double scale = (std::abs(stress[0]) + sc.penalty * delta) * L * kThickness;
        const std::string what = c.name() + (stretch ? " stretched" : " displaced") +
                                 (tractionTerm ? ", traction term" : "");
        wForce.update(std::hypot(r.sum[0] - ex, r.sum[1] - ey) / scale, [&] {
          return what + " " + at({{"fx", r.sum[0]}, {"fy", r.sum[1]}, {"ex", ex}, {"ey", ey}});
        });
        wReaction.update(std::hypot(r.reaction[0] - ex, r.reaction[1] - ey) / scale,
                         [&] { return what; });
        // The gap is |u - u_bar|: delta, or zero up to the rounding of x - X0 (x ~ 1).
        wGap.update(std::abs(r.gap - u) / delta, [&] { return what; });
      }
  }
  EXPECT_WORST_LE(wForce, 1e-12);
  EXPECT_WORST_LE(wReaction, 1e-12);
  EXPECT_WORST_LE(wGap, 1e-12); // rounding of x - X0, ~2e-16 |x|, against delta = 1e-3
  // Sign and size, spelled out once: pushed into +x, the constrained side pulls back.
  sc.penaltyTraction = false;
  Boundary bd;
  bd.setup(PETSC_COMM_SELF, sc, g, 1e-5);
  const double zero[3] = {0, 0, 0};
  const PenaltyResult r = penalty(sc, g, bd, kCases[0], delta, 0.0, zero);
  EXPECT_LT(r.sum[0], 0.0);
  EXPECT_NEAR(r.sum[0], -2.0e9 * 1.0e-3 * (6 * kH0) * kThickness, 1e-12 * std::abs(r.sum[0]));
}

// ---------------------------------------------------------------------------------------------
// 4. Setup: alpha and its bounds.

TEST(Boundary, PenaltySetupBounds) {
  Scene<2> sc = scene();
  DisplacementBC<2> d;
  d.side = static_cast<int>(Side::Left);
  sc.dbcs = {d};
  Grid<2> g;
  ASSERT_EQ(static_cast<int>(g.create(PETSC_COMM_SELF, sc.h, sc.levelBoxes(), sc.cracks)), 0);
  const double h = g.hMin(), rho = sc.material.rho, dt = 1.0e-5;
  const double M = sc.material.lambda + 2.0 * sc.material.mu;
  const double limit = 1.6 * rho * h / (dt * dt); // stable limit of the penalty spring
  const double low = 4.0 * M / h;                 // below it the traction term goes unstable
  ASSERT_LT(low, limit);
  {
    Boundary bd;
    sc.penalty = 0.5 * limit;
    EXPECT_NO_THROW(bd.setup(PETSC_COMM_SELF, sc, g, dt));
    EXPECT_EQ(bd.alpha(), 0.5 * limit);
  }
  {
    Boundary bd;
    sc.penalty = 1.01 * limit;
    EXPECT_THROW(bd.setup(PETSC_COMM_SELF, sc, g, dt), InputError);
    // A segment scale counts: 0.6 of the limit with scale 2 is beyond it.
    sc.penalty = 0.6 * limit;
    sc.dbcs[0].penaltyScale = 2.0;
    EXPECT_THROW(bd.setup(PETSC_COMM_SELF, sc, g, dt), InputError);
    sc.dbcs[0].penaltyScale = 1.0;
  }
  {
    Boundary bd;
    sc.penalty = 0.9 * low;
    sc.penaltyTraction = true;
    EXPECT_THROW(bd.setup(PETSC_COMM_SELF, sc, g, dt), InputError);
    sc.penaltyTraction = false;
    EXPECT_NO_THROW(bd.setup(PETSC_COMM_SELF, sc, g, dt));
    EXPECT_EQ(bd.alpha(), 0.9 * low);
  }
  {
    // Default: min(100 M / h, 0.5 rho h / dt^2); each branch by the choice of dt.
    sc.penalty = 0;
    sc.penaltyTraction = true;
    Boundary a, b;
    EXPECT_NO_THROW(a.setup(PETSC_COMM_SELF, sc, g, dt)); // 100 M / h < 0.5 rho h / dt^2
    EXPECT_NEAR(a.alpha(), 100.0 * M / h, 1e-14 * a.alpha());
    const double dtLarge = 1.0e-4; // 0.5 rho h / dt^2 = 2.3e9 < 100 M / h = 2.9e9
    EXPECT_NO_THROW(b.setup(PETSC_COMM_SELF, sc, g, dtLarge));
    EXPECT_NEAR(b.alpha(), 0.5 * rho * h / (dtLarge * dtLarge), 1e-14 * b.alpha());
  }
}

} // namespace
