// Unit tests of the particle <-> grid transfers in include/gimp/transfer/transfer.hpp on a
// three-level composite grid (ratios 2 and 4), with random particles that straddle level
// borders and reach transition nodes.
//
//   1. P2G conserves mass and momentum: sum_i m_i = sum_p m_p, sum_i p_i = sum_p m_p v_p
//      (partition of unity of the GIMP weights).
//   2. G2P of the nodal velocity p_i / m_i of particles that all move with one velocity u gives
//      back u (flip = 0), and moves them by dt u.
//   3. G2P with flip = 1 and a uniform nodal acceleration a gives v + dt a.
//   4. A linear nodal velocity field v_i = A x_i + b gives velocityGradient = A at every
//      particle and G2P moves each particle by dt (A x_p + b) (linear reproduction of the
//      weights and of their gradients).
//   5. PIC (flip = 0) conserves the total momentum through P2G -> p_i / m_i -> G2P.
//   6. APIC (transfer/affine.hpp): particles carrying an affine field v = A x + b (v_p, and
//      B_p = A D_p with D_p from the GIMP weights) give nodal velocities A x_i + b at every
//      node with mass, and G2P gives back v_p, B_p and C_p = B_p D_p^-1 = A.
//   7. APIC conserves angular momentum through P2G and G2P: sum_i x_i x m_i v_i equals
//      sum_p m_p (x_p x v_p + B_yx - B_xy) before and after.
//   8. Blocks (grid/stencils.hpp: a particle inside one level's regular nodes keeps its 1D
//      factors, and the kernels sum along one axis, then the other) give every kernel's result
//      the rows give (P2G, G2P, velocity gradient, internal force, APIC P2G and G2P, XPIC's
//      interpolation) to round-off, on a sample that holds both kinds.
//
// Tolerances are round-off: each particle's weights add up to 1 within a few ulp over its
// 4-25 nodes, and the sums over particles add ~1e-16 relative per term.
#include "gimp/grid/grid.hpp"
#include "gimp/input/scene.hpp"
#include "gimp/transfer/affine.hpp"
#include "gimp/transfer/internal_force.hpp"
#include "gimp/transfer/transfer.hpp"

#include "test_util.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace {

using gimp::Grid;
using gimp::LevelBox;
using gimp::Scene;
using gimp::test::at;
using gimp::test::Worst;
using Stencils = gimp::Stencils<2>;

// Domain origin and level-0 cell size that are not binary fractions (as in test_grid).
constexpr double kX0 = -1.3, kY0 = 0.7, kH0 = 0.37;

/// 14 x 12 level-0 cells; level 1 (ratio 2) over cells [4, 12] x [3, 9]; level 2 (ratio 4)
/// over [6.5, 8.5] x [4, 7.5], its left and right edges on level-1 lines between level-0 lines.
Scene<2> scene() {
  Scene<2> sc;
  sc.h = kH0;
  sc.domain = {kX0, kY0, kX0 + 14 * kH0, kY0 + 12 * kH0};
  sc.levels.assign(1, LevelBox<2>{sc.domain, 1});
  sc.levels.push_back(
      LevelBox<2>{{kX0 + 4 * kH0, kY0 + 3 * kH0, kX0 + 12 * kH0, kY0 + 9 * kH0}, 2});
  sc.levels.push_back(
      LevelBox<2>{{kX0 + 6.5 * kH0, kY0 + 4 * kH0, kX0 + 8.5 * kH0, kY0 + 7.5 * kH0}, 4});
  return sc;
}

struct Particles {
  PetscInt n = 0;
  std::vector<double> x, l, m, v;
};

/// n random particles over cells [2, 12] x [1.5, 10.5] (all three levels and their borders):
/// half-sizes between 0.05 and 0.5 of their leaf cell, masses in [0.5, 2], velocities in [-3, 3].
/// n particles of half-sizes between lmin and lmax of their leaf cell.
Particles randomParticles(const Grid<2> &g, PetscInt n, unsigned seed, double lmin = 0.05,
                          double lmax = 0.5) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> X(kX0 + 2 * kH0, kX0 + 12 * kH0),
      Y(kY0 + 1.5 * kH0, kY0 + 10.5 * kH0), frac(lmin, lmax), mass(0.5, 2.0), vel(-3.0, 3.0);
  Particles p;
  p.n = n;
  for (PetscInt k = 0; k < n; ++k) {
    const double x = X(rng), y = Y(rng);
    const double h = g.levels[g.leafLevelAt(x, y)].h;
    p.x.insert(p.x.end(), {x, y});
    p.l.insert(p.l.end(), {frac(rng) * h, frac(rng) * h});
    p.m.push_back(mass(rng));
    p.v.insert(p.v.end(), {vel(rng), vel(rng)});
  }
  return p;
}

struct Fixture {
  Grid<2> g;
  Particles p;
  Stencils st;
  long straddling = 0, transitionEntries = 0;

  explicit Fixture(unsigned seed, double lmin = 0.05, double lmax = 0.5) {
    EXPECT_EQ(static_cast<int>(g.create(PETSC_COMM_SELF, kH0, scene().levelBoxes())), 0);
    EXPECT_EQ(g.levels.size(), 3u);
    p = randomParticles(g, 3000, seed, lmin, lmax);
    EXPECT_TRUE(g.buildStencils(p.n, p.x.data(), p.l.data(), st));
    // The sample is not vacuous: particles cross level borders and reach transition nodes.
    for (PetscInt k = 0; k < p.n; ++k) {
      const double x = p.x[2 * k], y = p.x[2 * k + 1], lx = p.l[2 * k], ly = p.l[2 * k + 1];
      const int q = g.leafLevelAt(x, y);
      if (g.leafLevelAt(x - lx * 0.999, y - ly * 0.999) != q ||
          g.leafLevelAt(x + lx * 0.999, y + ly * 0.999) != q ||
          g.leafLevelAt(x - lx * 0.999, y + ly * 0.999) != q ||
          g.leafLevelAt(x + lx * 0.999, y - ly * 0.999) != q)
        ++straddling;
      for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e)
        transitionEntries += !g.regular[st.node[e]];
    }
    EXPECT_GT(straddling, 20);
    EXPECT_GT(transitionEntries, 100);
  }
  std::vector<double> nodal() const { return std::vector<double>(2 * g.nWindow, 0.0); }
};

constexpr double kEps = 2.220446049250313e-16;

/// What x_p + dt v_p - x_p may differ from dt v_p by: the rounding of the new position (half
/// an ulp of |x|, twice for safety) and 1e-13 of the step (the interpolated velocity).
double positionRoundOff(const std::vector<double> &x0, PetscInt k, double step) {
  return 2.0 * kEps * std::max(std::abs(x0[2 * k]), std::abs(x0[2 * k + 1])) + 1e-13 * step;
}

/// Nodal velocity p_i / m_i (zero where no mass).
std::vector<double> nodalVelocity(const std::vector<double> &mom, const std::vector<double> &mass) {
  std::vector<double> v(mom.size(), 0.0);
  for (size_t i = 0; i < mass.size() / 2; ++i)
    if (mass[2 * i] > 0) {
      v[2 * i] = mom[2 * i] / mass[2 * i];
      v[2 * i + 1] = mom[2 * i + 1] / mass[2 * i];
    }
  return v;
}

TEST(Transfer, P2GConservesMassAndMomentum) {
  Fixture f(1);
  std::printf("  %ld particles, %ld straddle a level border, %ld stencil entries at transition "
              "nodes\n",
              static_cast<long>(f.p.n), f.straddling, f.transitionEntries);
  std::vector<double> mom = f.nodal(), mass = f.nodal();
  gimp::transfer::particlesToGrid<2>(f.st, f.p.n, f.p.m.data(), f.p.v.data(), mom.data(),
                                     mass.data());
  double M = 0, P[2] = {0, 0}, Pabs = 0, Mg = 0, Pg[2] = {0, 0};
  for (PetscInt k = 0; k < f.p.n; ++k) {
    M += f.p.m[k];
    P[0] += f.p.m[k] * f.p.v[2 * k];
    P[1] += f.p.m[k] * f.p.v[2 * k + 1];
    Pabs += f.p.m[k] * std::hypot(f.p.v[2 * k], f.p.v[2 * k + 1]);
  }
  long massNodes = 0;
  for (PetscInt i = 0; i < f.g.nWindow; ++i) {
    Mg += mass[2 * i];
    Pg[0] += mom[2 * i];
    Pg[1] += mom[2 * i + 1];
    EXPECT_EQ(mass[2 * i + 1], 0.0); // mass lives in component 0 only
    if (mass[2 * i] > 0) {
      ++massNodes;
      EXPECT_TRUE(f.g.active[i]) << "mass on an inactive node " << i;
    }
  }
  const double eMass = std::abs(Mg - M) / M;
  // Momentum relative to sum m |v| (the total itself may nearly cancel).
  const double eMom = std::hypot(Pg[0] - P[0], Pg[1] - P[1]) / Pabs;
  std::printf("  mass: relative error %.2e over %ld nodes; momentum: %.2e\n", eMass, massNodes,
              eMom);
  EXPECT_LE(eMass, 1e-14);
  EXPECT_LE(eMom, 1e-14);
}

TEST(Transfer, UniformVelocityIsReproduced) {
  Fixture f(2);
  const double u[2] = {1.7, -0.45}, dt = 1.0e-3;
  for (PetscInt k = 0; k < f.p.n; ++k) {
    f.p.v[2 * k] = u[0];
    f.p.v[2 * k + 1] = u[1];
  }
  std::vector<double> mom = f.nodal(), mass = f.nodal();
  gimp::transfer::particlesToGrid<2>(f.st, f.p.n, f.p.m.data(), f.p.v.data(), mom.data(),
                                     mass.data());
  const std::vector<double> vg = nodalVelocity(mom, mass), ag = f.nodal();
  const std::vector<double> x0 = f.p.x;
  std::vector<double> v(2 * f.p.n, 99.0); // overwritten by flip = 0
  gimp::transfer::gridToParticles<2>(f.st, f.p.n, vg.data(), ag.data(), dt, 0.0, v.data(),
                                     f.p.x.data());
  Worst wv, wx;
  const double un = std::hypot(u[0], u[1]);
  for (PetscInt k = 0; k < f.p.n; ++k) {
    wv.update(std::hypot(v[2 * k] - u[0], v[2 * k + 1] - u[1]) / un, [&] {
      return at({{"particle", double(k)}});
    });
    wx.update(std::hypot(f.p.x[2 * k] - x0[2 * k] - dt * u[0],
                         f.p.x[2 * k + 1] - x0[2 * k + 1] - dt * u[1]) /
                  positionRoundOff(x0, k, dt * un),
              [&] {
                return at({{"particle", double(k)}});
              });
  }
  // p_i / m_i = u within an ulp; one particle's weights add up to 1 within ~2e-14 (measured
  // over 21000 particles; each weight is a quotient like (ua - ub)(ua + ub) / (2 lambda) of
  // differences of numbers near 1, good to ~eps / lambda <= 20 eps, over 4-25 nodes). The
  // sums of test 1 average these errors out; a single particle does not.
  EXPECT_WORST_LE(wv, 1e-13);
  EXPECT_WORST_LE(wx, 1.0); // in units of the rounding of x + dt v
}

TEST(Transfer, FlipAddsTheAcceleration) {
  Fixture f(3);
  const double a[2] = {-9.81, 4.2}, dt = 2.0e-3;
  std::vector<double> vg = f.nodal(), ag = f.nodal();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> U(-1, 1);
  for (PetscInt i = 0; i < f.g.nWindow; ++i) {
    vg[2 * i] = U(rng); // does not enter the FLIP velocity
    vg[2 * i + 1] = U(rng);
    ag[2 * i] = a[0];
    ag[2 * i + 1] = a[1];
  }
  const std::vector<double> v0 = f.p.v;
  gimp::transfer::gridToParticles<2>(f.st, f.p.n, vg.data(), ag.data(), dt, 1.0, f.p.v.data(),
                                     f.p.x.data());
  Worst w;
  for (PetscInt k = 0; k < f.p.n; ++k) {
    const double ex = v0[2 * k] + dt * a[0], ey = v0[2 * k + 1] + dt * a[1];
    w.update(std::hypot(f.p.v[2 * k] - ex, f.p.v[2 * k + 1] - ey) /
                 (std::hypot(v0[2 * k], v0[2 * k + 1]) + dt * std::hypot(a[0], a[1])),
             [&] {
               return at({{"particle", double(k)}});
             });
  }
  EXPECT_WORST_LE(w, 1e-14);
}

TEST(Transfer, LinearFieldGivesItsGradientAndMotion) {
  Fixture f(4);
  const double A[2][2] = {{0.8, -1.3}, {0.45, -0.2}}, b[2] = {0.3, -0.7}, dt = 1.0e-3;
  std::vector<double> vg = f.nodal(), ag = f.nodal();
  for (PetscInt i = 0; i < f.g.nWindow; ++i) {
    vg[2 * i] = A[0][0] * f.g.X[i] + A[0][1] * f.g.Y[i] + b[0];
    vg[2 * i + 1] = A[1][0] * f.g.X[i] + A[1][1] * f.g.Y[i] + b[1];
  }
  std::vector<double> L(4 * f.p.n);
  gimp::transfer::velocityGradient<2>(f.st, f.p.n, vg.data(), L.data());
  const std::vector<double> x0 = f.p.x;
  gimp::transfer::gridToParticles<2>(f.st, f.p.n, vg.data(), ag.data(), dt, 0.0, f.p.v.data(),
                                     f.p.x.data());
  Worst wL, wLabs, wv, wx;
  for (PetscInt k = 0; k < f.p.n; ++k) {
    double eL = 0, vmax = 0;
    for (int c = 0; c < 2; ++c)
      for (int d = 0; d < 2; ++d) // row-major: L(c, d) = d v_c / d x_d
        eL = std::max(eL, std::abs(L[4 * k + 2 * c + d] - A[c][d]));
    for (PetscInt e = f.st.start[k]; e < f.st.start[k + 1]; ++e)
      vmax = std::max(vmax, std::hypot(vg[2 * f.st.node[e]], vg[2 * f.st.node[e] + 1]));
    // Round-off of the gradient: the tent's argument x_p - x_i carries eps |x|, and a weight's
    // gradient (S(d + l) - S(d - l)) / (2 l) changes by 1 / (h l) per unit of it, so each
    // node's term v_i grad w_i is good to ~eps |v_i| (|x_p| + h) / (h l) (4e-11 for the
    // smallest particles, l = 0.05 h_min, at |x| = 3.5; 4e-14 for l = h / 2 near the origin).
    const double h = f.g.levels[f.g.leafLevelAt(x0[2 * k], x0[2 * k + 1])].h;
    const double lmin = std::min(f.p.l[2 * k], f.p.l[2 * k + 1]);
    const double scaleL = kEps * vmax * (std::hypot(x0[2 * k], x0[2 * k + 1]) + h) / (h * lmin);
    wL.update(eL / scaleL, [&] { return at({{"particle", double(k)}, {"err", eL}}); });
    wLabs.update(eL, [&] { return at({{"particle", double(k)}}); });
    const double vx = A[0][0] * x0[2 * k] + A[0][1] * x0[2 * k + 1] + b[0];
    const double vy = A[1][0] * x0[2 * k] + A[1][1] * x0[2 * k + 1] + b[1];
    wv.update(std::hypot(f.p.v[2 * k] - vx, f.p.v[2 * k + 1] - vy) / vmax, [&] {
      return at({{"particle", double(k)}});
    });
    wx.update(
        std::hypot(f.p.x[2 * k] - x0[2 * k] - dt * vx, f.p.x[2 * k + 1] - x0[2 * k + 1] - dt * vy) /
            positionRoundOff(x0, k, dt * std::hypot(vx, vy)),
        [&] {
          return at({{"particle", double(k)}});
        });
  }
  EXPECT_WORST_LE(wL, 4.0);      // in units of the round-off estimate above
  EXPECT_WORST_LE(wLabs, 1e-10); // absolute, |A| ~ 1 (for the record)
  EXPECT_WORST_LE(wv, 1e-13);    // relative to the largest nodal |v|, as test 2
  EXPECT_WORST_LE(wx, 1.0);      // in units of the rounding of x + dt v
}

TEST(Transfer, PicConservesMomentum) {
  Fixture f(5);
  std::vector<double> mom = f.nodal(), mass = f.nodal();
  gimp::transfer::particlesToGrid<2>(f.st, f.p.n, f.p.m.data(), f.p.v.data(), mom.data(),
                                     mass.data());
  const std::vector<double> vg = nodalVelocity(mom, mass), ag = f.nodal();
  double P0[2] = {0, 0}, Pabs = 0;
  for (PetscInt k = 0; k < f.p.n; ++k) {
    P0[0] += f.p.m[k] * f.p.v[2 * k];
    P0[1] += f.p.m[k] * f.p.v[2 * k + 1];
    Pabs += f.p.m[k] * std::hypot(f.p.v[2 * k], f.p.v[2 * k + 1]);
  }
  const std::vector<double> v0 = f.p.v;
  gimp::transfer::gridToParticles<2>(f.st, f.p.n, vg.data(), ag.data(), 1e-3, 0.0, f.p.v.data(),
                                     f.p.x.data());
  double P1[2] = {0, 0}, change = 0;
  for (PetscInt k = 0; k < f.p.n; ++k) {
    P1[0] += f.p.m[k] * f.p.v[2 * k];
    P1[1] += f.p.m[k] * f.p.v[2 * k + 1];
    change =
        std::max(change, std::hypot(f.p.v[2 * k] - v0[2 * k], f.p.v[2 * k + 1] - v0[2 * k + 1]));
  }
  // sum_p m_p sum_i w_ip v_i = sum_i m_i v_i = sum_i p_i = sum_p m_p v_p: round-off only,
  // relative to sum_p m_p |v_p|. The velocities themselves change (PIC smooths them).
  const double e = std::hypot(P1[0] - P0[0], P1[1] - P0[1]) / Pabs;
  std::printf("  PIC momentum: relative change %.2e; largest velocity change %.2f\n", e, change);
  EXPECT_LE(e, 1e-13);
  EXPECT_GT(change, 0.1);
}

/// The window's node coordinates, D per slot (no cracks: slot = node).
std::vector<double> slotCoordinates(const Grid<2> &g) {
  std::vector<double> xs(2 * g.nSlots);
  for (PetscInt s = 0; s < g.nSlots; ++s) {
    xs[2 * s] = g.X[g.slotNode[s]];
    xs[2 * s + 1] = g.Y[g.slotNode[s]];
  }
  return xs;
}

TEST(Transfer, ApicReproducesAnAffineField) {
  Fixture f(6);
  namespace tr = gimp::transfer;
  const double A[2][2] = {{0.8, -1.3}, {0.45, -0.2}}, b[2] = {0.3, -0.7};
  const std::vector<double> xs = slotCoordinates(f.g);
  std::vector<double> B(4 * f.p.n), C(4 * f.p.n);
  long notBSpline = 0; // particles whose D_p differs from the B-spline constant h^2 / 4
  for (PetscInt k = 0; k < f.p.n; ++k) {
    const double x = f.p.x[2 * k], y = f.p.x[2 * k + 1];
    f.p.v[2 * k] = A[0][0] * x + A[0][1] * y + b[0];
    f.p.v[2 * k + 1] = A[1][0] * x + A[1][1] * y + b[1];
    const gimp::Tensor<2> Dp = tr::inertia<2>(f.st, k, f.p.x.data(), xs.data());
    const double h = f.g.levels[f.g.leafLevelAt(x, y)].h;
    notBSpline += std::abs(Dp(0, 0) - 0.25 * h * h) > 1e-3 * h * h;
    for (int c = 0; c < 2; ++c)
      for (int d = 0; d < 2; ++d)
        B[4 * k + 2 * c + d] = A[c][0] * Dp(0, d) + A[c][1] * Dp(1, d);
  }
  EXPECT_GT(notBSpline, f.p.n / 2);
  tr::affineVelocity<2>(f.st, f.p.n, f.p.x.data(), xs.data(), B.data(), C.data());
  std::vector<double> mom = f.nodal(), mass = f.nodal();
  tr::particlesToGridAffine<2>(f.st, f.p.n, f.p.m.data(), f.p.v.data(), C.data(), f.p.x.data(),
                               xs.data(), mom.data(), mass.data());
  const std::vector<double> vg = nodalVelocity(mom, mass);
  Worst wg, wv, wB, wC;
  double vmax = 0;
  for (PetscInt i = 0; i < f.g.nWindow; ++i)
    vmax = std::max(vmax, std::hypot(A[0][0] * xs[2 * i] + A[0][1] * xs[2 * i + 1] + b[0],
                                     A[1][0] * xs[2 * i] + A[1][1] * xs[2 * i + 1] + b[1]));
  for (PetscInt i = 0; i < f.g.nWindow; ++i) {
    if (!(mass[2 * i] > 0)) continue;
    const double ex = A[0][0] * xs[2 * i] + A[0][1] * xs[2 * i + 1] + b[0];
    const double ey = A[1][0] * xs[2 * i] + A[1][1] * xs[2 * i + 1] + b[1];
    wg.update(std::hypot(vg[2 * i] - ex, vg[2 * i + 1] - ey) / vmax, [&] {
      return at({{"node", double(i)}, {"mass", mass[2 * i]}});
    });
  }
  const std::vector<double> v0 = f.p.v, B0 = B, x0 = f.p.x;
  std::fill(f.p.v.begin(), f.p.v.end(), 99.0);
  std::fill(B.begin(), B.end(), 99.0);
  tr::gridToParticlesAffine<2>(f.st, f.p.n, vg.data(), x0.data(), xs.data(), 0.0, f.p.v.data(),
                               B.data(), f.p.x.data());
  tr::affineVelocity<2>(f.st, f.p.n, x0.data(), xs.data(), B.data(), C.data());
  for (PetscInt k = 0; k < f.p.n; ++k) {
    const double h = f.g.levels[f.g.leafLevelAt(x0[2 * k], x0[2 * k + 1])].h;
    wv.update(std::hypot(f.p.v[2 * k] - v0[2 * k], f.p.v[2 * k + 1] - v0[2 * k + 1]) / vmax, [&] {
      return at({{"particle", double(k)}});
    });
    double eB = 0, eC = 0;
    for (int c = 0; c < 2; ++c)
      for (int d = 0; d < 2; ++d) {
        eB = std::max(eB, std::abs(B[4 * k + 2 * c + d] - B0[4 * k + 2 * c + d]));
        eC = std::max(eC, std::abs(C[4 * k + 2 * c + d] - A[c][d]));
      }
    // B_p ~ |v| h: relative to vmax h. C_p = B_p D_p^-1 carries B's round-off divided by
    // D_p's smallest eigenvalue (small near a node, where the weights concentrate).
    const Eigen::Vector2d ev = Eigen::SelfAdjointEigenSolver<gimp::Tensor<2>>(
                                   tr::inertia<2>(f.st, k, x0.data(), xs.data()))
                                   .eigenvalues();
    wB.update(eB / (vmax * h), [&] { return at({{"particle", double(k)}}); });
    wC.update(eC * ev.minCoeff() / (vmax * h), [&] {
      return at({{"particle", double(k)}, {"err", eC}});
    });
  }
  EXPECT_WORST_LE(wg, 1e-13); // nodal v_i = A x_i + b, relative to the largest |v|
  EXPECT_WORST_LE(wv, 1e-13);
  EXPECT_WORST_LE(wB, 1e-13);
  EXPECT_WORST_LE(wC, 1e-13);
}

TEST(Transfer, ApicConservesAngularMomentum) {
  Fixture f(7);
  namespace tr = gimp::transfer;
  const std::vector<double> xs = slotCoordinates(f.g);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> U(-2, 2);
  std::vector<double> B(4 * f.p.n), C(4 * f.p.n);
  for (double &e : B)
    e = U(rng) * 0.1;
  double scale = 0; // sum_p m_p |x_p| |v_p| and the spin's size
  for (PetscInt k = 0; k < f.p.n; ++k)
    scale += f.p.m[k] * (std::hypot(f.p.x[2 * k], f.p.x[2 * k + 1]) *
                             std::hypot(f.p.v[2 * k], f.p.v[2 * k + 1]) +
                         std::abs(B[4 * k + 2]) + std::abs(B[4 * k + 1]));
  const double L0 = tr::angularMomentum(f.p.n, f.p.m.data(), f.p.x.data(), f.p.v.data(), B.data());
  const double orbital =
      tr::angularMomentum(f.p.n, f.p.m.data(), f.p.x.data(), f.p.v.data(), nullptr);
  tr::affineVelocity<2>(f.st, f.p.n, f.p.x.data(), xs.data(), B.data(), C.data());
  std::vector<double> mom = f.nodal(), mass = f.nodal();
  tr::particlesToGridAffine<2>(f.st, f.p.n, f.p.m.data(), f.p.v.data(), C.data(), f.p.x.data(),
                               xs.data(), mom.data(), mass.data());
  double Lg = 0;
  for (PetscInt i = 0; i < f.g.nWindow; ++i)
    Lg += xs[2 * i] * mom[2 * i + 1] - xs[2 * i + 1] * mom[2 * i];
  const std::vector<double> vg = nodalVelocity(mom, mass), x0 = f.p.x;
  tr::gridToParticlesAffine<2>(f.st, f.p.n, vg.data(), x0.data(), xs.data(), 0.0, f.p.v.data(),
                               B.data(), f.p.x.data());
  const double L1 = tr::angularMomentum(f.p.n, f.p.m.data(), f.p.x.data(), f.p.v.data(), B.data());
  std::printf("  L: particles %.15g, grid %.15g, after G2P %.15g (without the spin %.6g)\n", L0, Lg,
              L1, orbital);
  EXPECT_LE(std::abs(Lg - L0) / scale, 1e-14);
  EXPECT_LE(std::abs(L1 - L0) / scale, 1e-14);
  EXPECT_GT(std::abs(orbital - L0) / scale, 1e-4); // the spin term matters in this sample
}

/// Every kernel gives the rows' results with the blocks of buildStencils(compact), for
/// particles of half-sizes between lmin and lmax of their cell; side: the blocks expected
/// (3: up to h/2, 4: beyond).
void blocksGiveTheRowsResults(unsigned seed, double lmin, double lmax, int side) {
  Fixture f(seed, lmin, lmax);
  Stencils blocks;
  ASSERT_TRUE(f.g.buildStencils(f.p.n, f.p.x.data(), f.p.l.data(), blocks, true));
  // Both kinds are present: blocks inside the levels, rows at their borders.
  PetscInt nBlocks = 0, nBlocks4 = 0;
  for (PetscInt k = 0; k < f.p.n; ++k) {
    if (side == 3) {
      EXPECT_FALSE(blocks.isBlock4(k)) << k;
    }
    const bool block = blocks.isBlock(k) || blocks.isBlock4(k);
    nBlocks += block;
    nBlocks4 += blocks.isBlock4(k);
    if (!block) continue;
    // A block's entries are the rows' entries (a last node of weight 0 may be left out).
    std::vector<std::pair<PetscInt, double>> a, b;
    blocks.forEach(k, [&](PetscInt s, double w, const gimp::Vector<2> &) { a.push_back({s, w}); });
    f.st.forEach(k, [&](PetscInt s, double w, const gimp::Vector<2> &) { b.push_back({s, w}); });
    // 3-node blocks hold the rows' very weights; 4-node blocks their closed form (round-off).
    const double wtol = side == 3 ? 0.0 : 1e-14;
    auto holds = [&](const std::vector<std::pair<PetscInt, double>> &in, const auto &e) {
      return std::count_if(in.begin(), in.end(), [&](const auto &c) {
               return c.first == e.first && std::abs(c.second - e.second) <= wtol;
             }) == 1;
    };
    for (const auto &e : b) // every row of nonzero weight is a block entry,
      EXPECT_TRUE(e.second == 0.0 || holds(a, e)) << k;
    for (const auto &e : a) // and every block entry of nonzero weight a row
      EXPECT_TRUE(e.second == 0.0 || holds(b, e)) << k;
  }
  if (side == 4) {
    EXPECT_GT(nBlocks4, 200);
  }
  // (The sample is made to straddle level borders, so most particles keep rows.)
  EXPECT_GT(nBlocks, 200);
  EXPECT_GT(f.p.n - nBlocks, 200);

  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> vg(2 * f.g.nWindow), ag(2 * f.g.nWindow), xs(2 * f.g.nWindow);
  for (auto &z : vg)
    z = u(rng);
  for (auto &z : ag)
    z = u(rng);
  for (PetscInt s = 0; s < f.g.nWindow; ++s) {
    xs[2 * s] = f.g.X[s];
    xs[2 * s + 1] = f.g.Y[s];
  }
  std::vector<double> stress(4 * f.p.n), V(f.p.n), B(4 * f.p.n);
  for (auto &z : stress)
    z = u(rng);
  for (auto &z : V)
    z = 1.0 + 0.5 * u(rng);
  for (auto &z : B)
    z = u(rng);

  // Largest difference relative to the largest value of two arrays.
  auto rel = [](const std::vector<double> &a, const std::vector<double> &b) {
    double d = 0, m = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      d = std::max(d, std::abs(a[i] - b[i]));
      m = std::max(m, std::abs(b[i]));
    }
    return d / m;
  };
  // Blocks sum the rows' products in another order (1e-14). 4-node blocks also take their
  // weights in closed form, up to 5.4e-15 from the rows' (ShapeExact.FourNodeClosedForm), which
  // the gradient sums of 16 nodes with slopes up to 1 / (2 l) carry: 4e-14.
  const double tol = side == 3 ? 1e-14 : 4e-14;
  {
    auto mom = f.nodal(), mass = f.nodal(), mom2 = f.nodal(), mass2 = f.nodal();
    gimp::transfer::particlesToGrid<2>(f.st, f.p.n, f.p.m.data(), f.p.v.data(), mom.data(),
                                       mass.data());
    gimp::transfer::particlesToGrid<2>(blocks, f.p.n, f.p.m.data(), f.p.v.data(), mom2.data(),
                                       mass2.data());
    EXPECT_LT(rel(mom2, mom), tol);
    EXPECT_LT(rel(mass2, mass), tol);
  }
  {
    auto v1 = f.p.v, v2 = f.p.v, x1 = f.p.x, x2 = f.p.x;
    gimp::transfer::gridToParticles<2>(f.st, f.p.n, vg.data(), ag.data(), 0.1, 0.7, v1.data(),
                                       x1.data());
    gimp::transfer::gridToParticles<2>(blocks, f.p.n, vg.data(), ag.data(), 0.1, 0.7, v2.data(),
                                       x2.data());
    EXPECT_LT(rel(v2, v1), tol);
    EXPECT_LT(rel(x2, x1), tol);
  }
  {
    std::vector<double> L1(4 * f.p.n), L2(4 * f.p.n);
    gimp::transfer::velocityGradient<2>(f.st, f.p.n, vg.data(), L1.data());
    gimp::transfer::velocityGradient<2>(blocks, f.p.n, vg.data(), L2.data());
    EXPECT_LT(rel(L2, L1), tol);
  }
  {
    auto f1 = f.nodal(), f2 = f.nodal();
    gimp::transfer::internalForce<2>(f.st, f.p.n, V.data(), stress.data(), f1.data());
    gimp::transfer::internalForce<2>(blocks, f.p.n, V.data(), stress.data(), f2.data());
    EXPECT_LT(rel(f2, f1), tol);
  }
  {
    auto mom = f.nodal(), mass = f.nodal(), mom2 = f.nodal(), mass2 = f.nodal();
    gimp::transfer::particlesToGridAffineB<2>(f.st, f.p.n, f.p.m.data(), f.p.v.data(), B.data(),
                                              f.p.x.data(), xs.data(), mom.data(), mass.data());
    gimp::transfer::particlesToGridAffineB<2>(blocks, f.p.n, f.p.m.data(), f.p.v.data(), B.data(),
                                              f.p.x.data(), xs.data(), mom2.data(), mass2.data());
    EXPECT_LT(rel(mom2, mom), 1e-12); // C_p = B_p D_p^-1: D_p^-1 amplifies round-off
    EXPECT_LT(rel(mass2, mass), tol);
  }
  {
    auto v1 = f.p.v, v2 = f.p.v, x1 = f.p.x, x2 = f.p.x;
    std::vector<double> B1(4 * f.p.n), B2(4 * f.p.n);
    gimp::transfer::gridToParticlesAffine<2>(f.st, f.p.n, vg.data(), f.p.x.data(), xs.data(), 0.1,
                                             v1.data(), B1.data(), x1.data());
    gimp::transfer::gridToParticlesAffine<2>(blocks, f.p.n, vg.data(), f.p.x.data(), xs.data(), 0.1,
                                             v2.data(), B2.data(), x2.data());
    EXPECT_LT(rel(v2, v1), tol);
    EXPECT_LT(rel(B2, B1), tol);
    EXPECT_LT(rel(x2, x1), tol);
  }
  {
    std::vector<double> o1(2 * f.p.n), o2(2 * f.p.n);
    gimp::transfer::interpolate<2>(f.st, f.p.n, vg.data(), o1.data());
    gimp::transfer::interpolate<2>(blocks, f.p.n, vg.data(), o2.data());
    EXPECT_LT(rel(o2, o1), tol);
  }
}

TEST(Transfer, BlocksGiveTheRowsResults) {
  blocksGiveTheRowsResults(8, 0.05, 0.5, 3);
}

// Particles stretched past half a cell (up to a whole one) along one axis or both keep 4-node
// blocks (the others 3-node blocks).
TEST(Transfer, FourNodeBlocksGiveTheRowsResults) {
  blocksGiveTheRowsResults(9, 0.3, 1.0, 4);
}

} // namespace
