// CPDI stencils in 3D (Grid<3>::buildCpdiStencils, src/grid/cpdi_stencils.cpp) on refined
// composite grids: a particle's domain is the hexahedron of its eight corners (the parallelepiped
// x_p + sum_a +-F r_a^0 of cpdi, or any convex hexahedron of tracked corners, cpdi2). The weights
// average the grid's point shape functions over it through the trilinear map, so on every
// layout, for parallelepipeds and for general hexahedra straddling level boxes:
//   sum_i S_ip = 1, sum_i S_ip x_i = the hexahedron's centroid,
//   sum_i grad S_ip = 0, sum_i grad S_ip (x) x_i = I,
// and the volume the weights use is the hexahedron's (cpdi::hexVolume; det F times the initial
// box for a parallelepiped). The centroid and volume of a general hexahedron are checked
// against a 4 x 4 x 4 Gauss rule written here, independently of the code's 2 x 2 x 2 one.
// A folded hexahedron or a corner outside the grid is reported. Sums are taken about the
// corners' mean and the centroid's error is measured in level-0 cells, as in test_cpdi.cpp.
// Every particle's entries are its corners' point shape functions in the order of their first
// appearance, bit for bit, whichever path of the build made them (also with a corner moved onto a
// node plane, where tents are exactly 0 or 1).
#include "cpdi_point_entries.hpp"
#include "gimp/grid/cpdi_cells.hpp"
#include "gimp/grid/grid.hpp"
#include "grid_layouts3d.hpp"

#include <gtest/gtest.h>
#include <petscsys.h>

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace {

using gimp::Grid;
using gimp::Stencils;
namespace t3 = gimp::test3d;

/// Volume and centroid of the hexahedron c (cpdi_cells.hpp order) by 4 x 4 x 4 Gauss points.
void hexMoments(const double *c, double &V, double x[3]) {
  const double g[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                       0.8611363115940526};
  const double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                       0.3478548451374538};
  V = 0;
  x[0] = x[1] = x[2] = 0;
  for (int i = 0; i < 64; ++i) {
    const double xi[3] = {g[i % 4], g[(i / 4) % 4], g[i / 16]};
    const double wt = w[i % 4] * w[(i / 4) % 4] * w[i / 16];
    double J[3][3] = {}, p[3] = {};
    for (int q = 0; q < 8; ++q) {
      double f[3], s[3];
      for (int a = 0; a < 3; ++a) {
        s[a] = gimp::cpdi::cornerSign<3>(q, a);
        f[a] = 0.5 * (1 + s[a] * xi[a]);
      }
      const double dM[3] = {0.5 * s[0] * f[1] * f[2], 0.5 * s[1] * f[0] * f[2],
                            0.5 * s[2] * f[0] * f[1]};
      for (int r = 0; r < 3; ++r) {
        p[r] += f[0] * f[1] * f[2] * c[3 * q + r];
        for (int j = 0; j < 3; ++j)
          J[r][j] += c[3 * q + r] * dM[j];
      }
    }
    const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
                       J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                       J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
    V += wt * det;
    for (int r = 0; r < 3; ++r)
      x[r] += wt * det * p[r];
  }
  for (int r = 0; r < 3; ++r)
    x[r] /= V;
}

/// A random hexahedron around x of half-sizes l: the parallelepiped of a random F near I
/// (rotation, shear, stretch), its corners then moved by up to `jitter` of l (0: cpdi's).
std::array<double, 24> randomHex(std::mt19937_64 &rng, const double *x, const double *l,
                                 double jitter) {
  std::uniform_real_distribution<double> u(-1, 1);
  double F[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      F[i][j] = (i == j ? 1.0 + 0.3 * u(rng) : 0.35 * u(rng));
  std::array<double, 24> c{};
  for (int q = 0; q < 8; ++q)
    for (int d = 0; d < 3; ++d) {
      double v = x[d];
      for (int a = 0; a < 3; ++a)
        v += gimp::cpdi::cornerSign<3>(q, a) * F[d][a] * l[a];
      c[3 * q + d] = v + jitter * l[d] * u(rng);
    }
  return c;
}

bool insideDomain(const Grid<3> &g, const double *c) {
  for (int q = 0; q < 8; ++q)
    for (int a = 0; a < 3; ++a) {
      const double lo = g.levels[0].box[a], hi = g.levels[0].box[3 + a];
      if (!(c[3 * q + a] > lo + 1e-9 && c[3 * q + a] < hi - 1e-9)) return false;
    }
  return true;
}

/// For each layout, random hexahedra (parallelepipeds when jitter is 0) inside the domain, their
/// stencils built one at a time; f(grid, corners, stencils, layout name).
template <class F> void onRandomHexes(double jitter, int perLayout, F &&f) {
  std::mt19937_64 rng(jitter > 0 ? 29 : 17);
  std::vector<t3::Layout> layouts = t3::twoLevelLayouts();
  for (const t3::Layout &l : t3::threeLevelLayouts())
    layouts.push_back(l);
  for (const t3::Layout &lay : layouts) {
    Grid<3> g;
    ASSERT_EQ(g.create(PETSC_COMM_SELF, t3::kH0, t3::boxesOf(lay)), 0) << lay.name;
    for (int n = 0; n < perLayout;) {
      double x[3], l[3];
      t3::drawParticle(g, rng, x, l);
      for (int a = 0; a < 3; ++a)
        l[a] *= 0.8; // keep the sheared corners within h0 of the particle
      const std::array<double, 24> c = randomHex(rng, x, l, jitter);
      if (!insideDomain(g, c.data())) continue;
      Stencils<3> s;
      const char *why = g.buildCpdiStencils(1, c.data(), s);
      ASSERT_EQ(why, nullptr) << lay.name;
      f(g, c, s, lay.name);
      ++n;
    }
  }
}

/// The identities of one particle's stencil (sums about the corners' mean, no cancellation):
/// worst[0] |sum S - 1|, [1] the centroid's error in level-0 cells, [2] |sum grad S| times the
/// domain's size, [3] |sum grad S (x) x - I|.
void checkOne(const Grid<3> &g, const std::array<double, 24> &c, const Stencils<3> &s,
              const std::string &name, double worst[4]) {
  double V = 0, xc[3], o[3] = {};
  hexMoments(c.data(), V, xc);
  EXPECT_NEAR(gimp::cpdi::hexVolume(c.data()), V, 1e-12 * V) << name;
  for (int q = 0; q < 8; ++q)
    for (int a = 0; a < 3; ++a)
      o[a] += c[3 * q + a] / 8;
  double S = 0, Sx[3] = {}, G[3] = {}, GX[3][3] = {};
  for (PetscInt e = s.start[0]; e < s.start[1]; ++e) {
    S += s.sw[e];
    for (int a = 0; a < 3; ++a) {
      Sx[a] += s.sw[e] * (g.coordinates(a)[s.node[e]] - o[a]);
      G[a] += s.sg[a][e];
      for (int b = 0; b < 3; ++b)
        GX[a][b] += s.sg[a][e] * (g.coordinates(b)[s.node[e]] - o[b]);
    }
  }
  worst[0] = std::max(worst[0], std::fabs(S - 1));
  for (int a = 0; a < 3; ++a) {
    worst[1] = std::max(worst[1], std::fabs(Sx[a] - (xc[a] - o[a])) / g.h0());
    worst[2] = std::max(worst[2], std::fabs(G[a]) * std::cbrt(V));
    for (int b = 0; b < 3; ++b)
      worst[3] = std::max(worst[3], std::fabs(GX[a][b] - (a == b ? 1.0 : 0.0)));
  }
}

void identities(double jitter) {
  double worst[4] = {0, 0, 0, 0};
  onRandomHexes(jitter, 40,
                [&](const Grid<3> &g, const std::array<double, 24> &c, const Stencils<3> &s,
                    const std::string &name) { checkOne(g, c, s, name, worst); });
  EXPECT_LT(worst[0], 1e-13);
  EXPECT_LT(worst[1], 1e-13);
  EXPECT_LT(worst[2], 1e-12);
  EXPECT_LT(worst[3], 1e-12);
  std::printf("partition %.1e, centroid %.1e, gradient sum %.1e, gradient moments %.1e\n", worst[0],
              worst[1], worst[2], worst[3]);
}

TEST(Cpdi3D, ParallelepipedIdentities) {
  identities(0.0);
}

TEST(Cpdi3D, HexahedronIdentities) {
  identities(0.15);
}

TEST(Cpdi3D, CornerWeightsAreThePointShapesInOrder) {
  int n = 0;
  onRandomHexes(0.15, 60,
                [&](const Grid<3> &g, const std::array<double, 24> &c, const Stencils<3> &s,
                    const std::string &name) {
                  gimp::test::expectPointShapeEntries<3>(g, c.data(), s, 0, name);
                  std::array<double, 24> d = c; // moved: corner n % 8 on a level-0 node plane
                  const int a = n % 3;
                  const double o = g.levels[0].box[a], h0 = g.h0(), x = d[3 * (n % 8) + a];
                  const double dx = o + std::round((x - o) / h0) * h0 - x;
                  for (int q = 0; q < 8; ++q)
                    d[3 * q + a] += dx;
                  ++n;
                  if (!insideDomain(g, d.data())) return;
                  Stencils<3> t;
                  if (g.buildCpdiStencils(1, d.data(), t) == nullptr)
                    gimp::test::expectPointShapeEntries<3>(g, d.data(), t, 0, name + " (snapped)");
                });
}

TEST(Cpdi3D, ParallelepipedVolumeIsDetFTimesTheBox) {
  const double F[3][3] = {{1.2, 0.3, -0.1}, {-0.2, 0.9, 0.25}, {0.05, -0.15, 1.1}};
  const double l[3] = {0.1, 0.2, 0.15};
  double c[24];
  for (int q = 0; q < 8; ++q)
    for (int d = 0; d < 3; ++d) {
      c[3 * q + d] = 0.5;
      for (int a = 0; a < 3; ++a)
        c[3 * q + d] += gimp::cpdi::cornerSign<3>(q, a) * F[d][a] * l[a];
    }
  const double det = F[0][0] * (F[1][1] * F[2][2] - F[1][2] * F[2][1]) -
                     F[0][1] * (F[1][0] * F[2][2] - F[1][2] * F[2][0]) +
                     F[0][2] * (F[1][0] * F[2][1] - F[1][1] * F[2][0]);
  EXPECT_NEAR(gimp::cpdi::hexVolume(c), det * 8 * l[0] * l[1] * l[2], 1e-15);
}

TEST(Cpdi3D, FoldedHexahedronOrCornerOutsideIsReported) {
  const t3::Layout lay = t3::twoLevelLayouts()[0];
  Grid<3> g;
  ASSERT_EQ(g.create(PETSC_COMM_SELF, t3::kH0, t3::boxesOf(lay)), 0);
  const double x[3] = {t3::kX0 + 2.5 * t3::kH0, t3::kY0 + 2.5 * t3::kH0, t3::kZ0 + 2.5 * t3::kH0};
  const double l[3] = {0.1, 0.1, 0.1};
  std::mt19937_64 rng(3);
  std::array<double, 24> c = randomHex(rng, x, l, 0.0);
  Stencils<3> s;
  EXPECT_EQ(g.buildCpdiStencils(1, c.data(), s), nullptr);
  std::swap(c[0], c[3 * 6]); // corner 0 and corner 6 trade places: the map folds
  std::swap(c[1], c[3 * 6 + 1]);
  std::swap(c[2], c[3 * 6 + 2]);
  const char *folded = g.buildCpdiStencils(1, c.data(), s);
  ASSERT_NE(folded, nullptr);
  EXPECT_NE(std::string(folded).find("inverted or collapsed"), std::string::npos);
  c = randomHex(rng, x, l, 0.0);
  c[0] = g.levels[0].box[0] - 0.01; // a corner outside the grid
  const char *outside = g.buildCpdiStencils(1, c.data(), s);
  ASSERT_NE(outside, nullptr);
  EXPECT_NE(std::string(outside).find("outside the grid"), std::string::npos);
}

} // namespace
