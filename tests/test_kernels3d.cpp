// The solver's particle-grid kernels in 3D on composite grids of three levels (GridT<3>
// stencils, rows and 3 x 3 x 3 blocks):
//
//   1. Internal-force patch test. A box B is tiled by particles (every leaf cell inside B split
//      into n^3 particles of that cell's size), each with the same Cauchy stress sigma. Since the
//      GIMP weight averages the node's shape function S_i over the particle, the kernel's
//      f_i = - sum_p V_p sigma . grad w_ip equals - boundary integral of S_i sigma . n over B's
//      faces. So: nodes whose support lies inside B carry no force; the forces sum to zero; and
//      for one stress component at a time the nodes on one side of B's middle carry the face
//      resultant (sigma_aa A_a along a for a normal stress; sigma_ab A_a along b for a shear).
//   2. Transfers of an affine velocity v(x) = a + G x: APIC's P2G (C_p = B_p D_p^-1) puts v(x_i)
//      on every node with mass and its G2P gives back v(x_p) and C_p = G; the velocity gradient
//      at every particle is G; mass and momentum are conserved by P2G (APIC and FLIP).
//
// Each layout runs with B on level-0 lines and with the particles shifted by a fraction of a
// level-0 cell along every axis (particles straddling level boundaries).
#include "gimp/grid/grid.hpp"
#include "gimp/transfer/affine.hpp"
#include "gimp/transfer/internal_force.hpp"
#include "gimp/transfer/transfer.hpp"

#include "grid_layouts3d.hpp"
#include "test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace {

using gimp::test::Worst;
using gimp::test3d::boxesOf;
using gimp::test3d::D;
using gimp::test3d::kH0;
using gimp::test3d::Layout;
using gimp::test3d::threeLevelLayouts;
using Grid3 = gimp::Grid<D>;
using Stencils3 = gimp::Stencils<D>;
using Index = gimp::LatticeIndex<D>;

struct Particles {
  std::vector<double> x, l, V;
  PetscInt size() const { return static_cast<PetscInt>(V.size()); }
};

/// Particles tiling B (on level-0 lines): every leaf cell inside B split into n^3, then all
/// moved by `shift` (metres per axis).
Particles tile(const Grid3 &g, const std::array<double, 6> &B, int n, const double *shift) {
  Particles p;
  for (int k = 0; k < static_cast<int>(g.levels.size()); ++k) {
    const gimp::Level<D> &L = g.levels[k];
    std::array<PetscInt, D> cells;
    for (int a = 0; a < D; ++a)
      cells[a] = L.n[a] - 1;
    gimp::forEachIndex<D>(cells, [&](const Index &c) {
      double lo[D], centre[D];
      bool in = true;
      for (int a = 0; a < D; ++a) {
        lo[a] = L.box[a] + c[a] * L.h;
        centre[a] = lo[a] + 0.5 * L.h;
        in = in && centre[a] > B[a] && centre[a] < B[D + a];
      }
      if (!in || g.leafLevelAt(centre) != k) return;
      const double d = L.h / n;
      std::array<PetscInt, D> sub{n, n, n};
      gimp::forEachIndex<D>(sub, [&](const Index &s) {
        for (int a = 0; a < D; ++a) {
          p.x.push_back(lo[a] + (s[a] + 0.5) * d + shift[a]);
          p.l.push_back(0.5 * d);
        }
        p.V.push_back(d * d * d);
      });
    });
  }
  return p;
}

/// The window coordinates of every slot, D per slot.
std::vector<double> slotCoordinates(const Grid3 &g) {
  std::vector<double> xs(D * g.nSlots);
  for (PetscInt s = 0; s < g.nSlots; ++s)
    for (int a = 0; a < D; ++a)
      xs[D * s + a] = g.coordinates(a)[g.slotNode[s]];
  return xs;
}

// ---------------------------------------------------------------------------------------------
// 1. Internal forces of a uniformly stressed tiled box.

struct PatchResult {
  Worst interior, sum, resultant, offAxis;
  long particles = 0, blocks = 0, interiorNodes = 0;
};

void patchLayout(const Layout &lay, int n, bool shifted, PatchResult &res) {
  Grid3 g;
  ASSERT_EQ(static_cast<int>(g.create(PETSC_COMM_SELF, kH0, boxesOf(lay))), 0);
  const double *o = g.origin.data();
  // B: level-0 cells [1, 5] x [1, 4] x [1, 3] of the 6 x 5 x 4 domain.
  std::array<double, 6> B = {o[0] + 1 * kH0, o[1] + 1 * kH0, o[2] + 1 * kH0,
                             o[0] + 5 * kH0, o[1] + 4 * kH0, o[2] + 3 * kH0};
  double shift[3] = {0, 0, 0};
  if (shifted) shift[0] = 0.31 * kH0, shift[1] = -0.23 * kH0, shift[2] = 0.17 * kH0;
  const Particles p = tile(g, B, n, shift);
  for (int a = 0; a < D; ++a) {
    B[a] += shift[a];
    B[D + a] += shift[a];
  }
  Stencils3 st;
  ASSERT_TRUE(g.buildStencils(p.size(), p.x.data(), p.l.data(), st, true));
  res.particles += p.size();
  for (PetscInt k = 0; k < p.size(); ++k)
    res.blocks += st.isBlock(k);
  double area[3];
  for (int a = 0; a < D; ++a)
    area[a] = (B[D + (a + 1) % D] - B[(a + 1) % D]) * (B[D + (a + 2) % D] - B[(a + 2) % D]);
  // The six stress components one at a time: (a, b) with sigma_ab = sigma_ba = s.
  const int comps[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};
  const double s = 2.5e6;
  for (const auto &ab : comps) {
    const int a = ab[0], b = ab[1];
    std::vector<double> sigma(gimp::kStress<D> * p.size(), 0.0);
    gimp::Tensor<D> t = gimp::Tensor<D>::Zero();
    t(a, b) = t(b, a) = s;
    for (PetscInt k = 0; k < p.size(); ++k)
      gimp::setStress<D>(sigma.data(), k, t);
    std::vector<double> f(D * g.nSlots, 0.0);
    gimp::transfer::internalForce<D>(st, p.size(), p.V.data(), sigma.data(), f.data());
    double fmax = 0;
    long double total[3] = {0, 0, 0};
    for (PetscInt nd = 0; nd < g.nSlots; ++nd)
      for (int c = 0; c < D; ++c) {
        fmax = std::max(fmax, std::abs(f[D * nd + c]));
        total[c] += f[D * nd + c];
      }
    // The forces cancel in the sum particle by particle (sum_i grad w_ip = 0): their round-off
    // is measured against the particles' gross force sum_p V_p s / l_p.
    double gross = 0;
    for (PetscInt k = 0; k < p.size(); ++k)
      gross += p.V[k] * s / p.l[D * k];
    auto where = [&] {
      return lay.name + " n=" + std::to_string(n) + (shifted ? " shifted" : "") + " sigma_" +
             std::to_string(a) + std::to_string(b);
    };
    // Interior nodes: support strictly inside B.
    double interior = 0;
    for (PetscInt nd = 0; nd < g.nWindow; ++nd) {
      if (!g.active[nd]) continue;
      const double *z = &g.zone[2 * D * nd];
      bool in = true;
      for (int c = 0; c < D; ++c) {
        const double X = g.coordinates(c)[nd];
        in = in && X - z[2 * c] > B[c] && X + z[2 * c + 1] < B[D + c];
      }
      if (!in) continue;
      ++res.interiorNodes;
      for (int c = 0; c < D; ++c)
        interior = std::max(interior, std::abs(f[D * nd + c]));
    }
    res.interior.update(interior / fmax, where);
    res.sum.update(static_cast<double>(
                       std::max({std::abs(total[0]), std::abs(total[1]), std::abs(total[2])})) /
                       gross,
                   where);
    // Face resultants: component b of the nodes below B's middle along a is s A_a, and the
    // same with a and b exchanged; the third component carries nothing.
    auto below = [&](int axis, int comp) {
      const double mid = 0.5 * (B[axis] + B[D + axis]);
      double r = 0;
      for (PetscInt nd = 0; nd < g.nWindow; ++nd)
        if (g.active[nd] && g.coordinates(axis)[nd] < mid) r += f[D * nd + comp];
      return r;
    };
    double err = std::abs(below(a, b) - s * area[a]) / (s * area[a]);
    err = std::max(err, std::abs(below(b, a) - s * area[b]) / (s * area[b]));
    res.resultant.update(err, where);
    double off = 0;
    for (int c = 0; c < D; ++c)
      if (c != a && c != b)
        for (PetscInt nd = 0; nd < g.nWindow; ++nd)
          off = std::max(off, std::abs(f[D * nd + c]));
    res.offAxis.update(off / fmax, where);
  }
}

TEST(Kernels3D, InternalForcePatchOnThreeLevels) {
  PatchResult res;
  const std::vector<Layout> layouts = threeLevelLayouts();
  for (size_t k = 0; k < layouts.size(); ++k)
    for (bool shifted : {false, true})
      patchLayout(layouts[k], k < 6 ? 2 : 1, shifted, res); // n = 2 on the ratio (2, 2) layouts
  EXPECT_WORST_LE(res.interior, 1e-12);
  EXPECT_WORST_LE(res.sum, 1e-12);
  EXPECT_WORST_LE(res.resultant, 1e-12);
  EXPECT_WORST_LE(res.offAxis, 1e-12);
  std::printf("  particles %ld (blocks %ld), interior nodes checked %ld\n", res.particles,
              res.blocks, res.interiorNodes);
  EXPECT_GT(res.blocks, res.particles / 100);
  EXPECT_GT(res.interiorNodes, 1000);
}

// ---------------------------------------------------------------------------------------------
// 2. Transfers of an affine velocity field.

struct AffineResult {
  Worst nodal, velocity, affine, gradient, mass, momentum, flipMomentum;
  long particles = 0, nodes = 0;
};

void affineLayout(const Layout &lay, bool shifted, AffineResult &res) {
  Grid3 g;
  ASSERT_EQ(static_cast<int>(g.create(PETSC_COMM_SELF, kH0, boxesOf(lay))), 0);
  const double *o = g.origin.data();
  const std::array<double, 6> B = {o[0] + 1 * kH0, o[1] + 1 * kH0, o[2] + 1 * kH0,
                                   o[0] + 5 * kH0, o[1] + 4 * kH0, o[2] + 3 * kH0};
  double shift[3] = {0, 0, 0};
  if (shifted) shift[0] = -0.29 * kH0, shift[1] = 0.37 * kH0, shift[2] = -0.11 * kH0;
  const Particles p = tile(g, B, 1, shift);
  const PetscInt n = p.size();
  Stencils3 st;
  ASSERT_TRUE(g.buildStencils(n, p.x.data(), p.l.data(), st, true));
  const std::vector<double> xs = slotCoordinates(g);
  // v(x) = a + G (x - o), G not symmetric.
  const double av[3] = {1.5, -0.7, 0.4};
  const double G[3][3] = {{0.3, -1.1, 0.2}, {0.8, 0.1, -0.5}, {-0.4, 0.6, -0.2}};
  auto field = [&](const double *x, double *v) {
    for (int c = 0; c < D; ++c) {
      v[c] = av[c];
      for (int e = 0; e < D; ++e)
        v[c] += G[c][e] * (x[e] - o[e]);
    }
  };
  std::vector<double> m(n), v(D * n), Bm(9 * n);
  long double mass = 0, mom[3] = {0, 0, 0}; // (long double: sums of 1e5 terms)
  for (PetscInt k = 0; k < n; ++k) {
    m[k] = 7800.0 * p.V[k];
    field(&p.x[D * k], &v[D * k]);
    // B_p = G D_p, so that C_p = B_p D_p^-1 = G.
    const gimp::Tensor<D> Dp = gimp::transfer::inertia<D>(st, k, p.x.data(), xs.data());
    for (int c = 0; c < D; ++c)
      for (int e = 0; e < D; ++e) {
        double s = 0;
        for (int q = 0; q < D; ++q)
          s += G[c][q] * Dp(q, e);
        Bm[9 * k + 3 * c + e] = s;
      }
    mass += m[k];
    for (int c = 0; c < D; ++c)
      mom[c] += m[k] * v[D * k + c];
  }
  res.particles += n;
  const std::string name = lay.name + (shifted ? " shifted" : "");
  auto where = [&] { return name; };

  // APIC P2G: every node with mass carries v(x_i).
  std::vector<double> pg(D * g.nSlots, 0.0), mg(D * g.nSlots, 0.0), vg(D * g.nSlots, 0.0);
  gimp::transfer::particlesToGridAffineB<D>(st, n, m.data(), v.data(), Bm.data(), p.x.data(),
                                            xs.data(), pg.data(), mg.data());
  double nodal = 0, vscale = 0;
  long double msum = 0, psum[3] = {0, 0, 0};
  for (PetscInt nd = 0; nd < g.nSlots; ++nd) {
    msum += mg[D * nd];
    for (int c = 0; c < D; ++c)
      psum[c] += pg[D * nd + c];
    if (mg[D * nd] <= 1e-12 * static_cast<double>(mass) / n) continue;
    ++res.nodes;
    double ve[3];
    field(&xs[D * nd], ve);
    for (int c = 0; c < D; ++c) {
      vg[D * nd + c] = pg[D * nd + c] / mg[D * nd];
      nodal = std::max(nodal, std::abs(vg[D * nd + c] - ve[c]));
      vscale = std::max(vscale, std::abs(ve[c]));
    }
  }
  res.nodal.update(nodal / vscale, where);
  res.mass.update(static_cast<double>(std::abs(msum - mass) / mass), where);
  const long double pscale = std::max({std::abs(mom[0]), std::abs(mom[1]), std::abs(mom[2])});
  double perr = 0;
  for (int c = 0; c < D; ++c)
    perr = std::max(perr, static_cast<double>(std::abs(psum[c] - mom[c]) / pscale));
  res.momentum.update(perr, where);

  // APIC G2P and the velocity gradient: v(x_p), C_p = G and L_p = G at every particle.
  std::vector<double> v2(D * n), B2(9 * n), L(9 * n);
  gimp::transfer::gridToParticlesAffine<D>(st, n, vg.data(), p.x.data(), xs.data(), 0.0, v2.data(),
                                           B2.data(), nullptr);
  gimp::transfer::velocityGradient<D>(st, n, vg.data(), L.data());
  double verr = 0, cerr = 0, lerr = 0, gscale = 0;
  for (int c = 0; c < D; ++c)
    for (int e = 0; e < D; ++e)
      gscale = std::max(gscale, std::abs(G[c][e]));
  for (PetscInt k = 0; k < n; ++k) {
    const gimp::Tensor<D> C =
        gimp::product<D>(gimp::tensorAt<D>(B2.data(), k),
                         gimp::transfer::inverseInertia<D>(st, k, p.x.data(), xs.data()));
    for (int c = 0; c < D; ++c) {
      verr = std::max(verr, std::abs(v2[D * k + c] - v[D * k + c]));
      for (int e = 0; e < D; ++e) {
        cerr = std::max(cerr, std::abs(C(c, e) - G[c][e]));
        lerr = std::max(lerr, std::abs(L[9 * k + 3 * c + e] - G[c][e]));
      }
    }
  }
  res.velocity.update(verr / vscale, where);
  res.affine.update(cerr / gscale, where);
  res.gradient.update(lerr / gscale, where);

  // FLIP/PIC P2G conserves mass and momentum too.
  std::fill(pg.begin(), pg.end(), 0.0);
  std::fill(mg.begin(), mg.end(), 0.0);
  gimp::transfer::particlesToGrid<D>(st, n, m.data(), v.data(), pg.data(), mg.data());
  long double fp[3] = {0, 0, 0}, fm = 0;
  for (PetscInt nd = 0; nd < g.nSlots; ++nd) {
    fm += mg[D * nd];
    for (int c = 0; c < D; ++c)
      fp[c] += pg[D * nd + c];
  }
  double ferr = static_cast<double>(std::abs(fm - mass) / mass);
  for (int c = 0; c < D; ++c)
    ferr = std::max(ferr, static_cast<double>(std::abs(fp[c] - mom[c]) / pscale));
  res.flipMomentum.update(ferr, where);
}

TEST(Kernels3D, AffineVelocityOnThreeLevels) {
  AffineResult res;
  for (const Layout &lay : threeLevelLayouts())
    for (bool shifted : {false, true})
      affineLayout(lay, shifted, res);
  EXPECT_WORST_LE(res.nodal, 1e-12);
  EXPECT_WORST_LE(res.velocity, 1e-12);
  EXPECT_WORST_LE(res.affine, 1e-10);
  EXPECT_WORST_LE(res.gradient, 1e-10);
  EXPECT_WORST_LE(res.mass, 1e-13);
  EXPECT_WORST_LE(res.momentum, 1e-13);
  EXPECT_WORST_LE(res.flipMomentum, 1e-13);
  std::printf("  particles %ld, nodes with mass %ld\n", res.particles, res.nodes);
}

} // namespace
