// Unit tests of the CPDI stencils (Grid::buildCpdiStencils, Sadeghirad et al. 2011, 2013) on the
// composite grids of grid_layouts.hpp (3 levels, ratios 2 to 4):
//
//   1. Random particles (rotations by any angle and by 45 degrees, shear, stretch; cpdi's
//      parallelograms and cpdi2's general quadrilaterals): partition of unity, linear
//      reproduction of the domain's centroid, sum grad S = 0, sum grad S (x) x_i = I, every
//      entry an active window node listed once with S >= 0.
//   2. The gradient is the derivative of the weight with respect to translating a parallelogram
//      whose corners lie in one cell of every tent (N_i bilinear over it; central differences).
//      CPDI's gradient is the exact gradient of its interpolated field (1/A) int grad sum_c M_c
//      N_i(x_c), its weight the average of that field: across a kink of N_i the two are
//      consistent (test 1) but not each other's derivative, so only this case is exact.
//   3. A rotated square inside one cell: its weights are the averages of N_i over its true area
//      (a brute-force midpoint rule over the rotated square). Rotated squares anywhere: every
//      node with a weight has a support that meets the true square; the axis-aligned box that
//      corner tracking spans gives weight to nodes whose supports miss it.
//   4. A corner outside the grid and an inverted quad are reported, not crashed on.
//   5. A block of particles rotated by 45 degrees under a uniform stress (a 3-level grid):
//      the internal force (the solver's kernel) vanishes at every node whose support lies inside
//      the block, so the patch stays at rest with its stress uniform; the axis-aligned boxes of
//      corner tracking leave out-of-balance forces there.
//   7. Every particle's entries are its corners' point shape functions (Grid::pointShapes) in the
//      order of their first appearance, bit for bit, whichever path built them (also with the
//      quads moved so that a corner lies on a node line, where tents are exactly 0 or 1).
//   6. APIC on cpdi2's quadrilaterals: with its moments about the weights' centroid
//      (transfer::weightCentroids) an affine nodal velocity gives C_p = B_p D_p^-1 = its gradient
//      and v_p its value at the centroid; about the corners' mean (not the centroid of a
//      general quad) C_p picks up v_p times the offset.
#include "gimp/grid/grid.hpp"
#include "gimp/transfer/affine.hpp"
#include "gimp/transfer/internal_force.hpp"

#include "cpdi_point_entries.hpp"
#include "grid_layouts.hpp"
#include "test_util.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <vector>

namespace {

using gimp::Grid;
using gimp::test::at;
using gimp::test::makeGrid;
using gimp::test::Sampler;
using gimp::test::sceneOf;
using gimp::test::threeLevelLayouts;
using gimp::test::Worst;
using Stencils = gimp::Stencils<2>;

/// A random domain around (x, y) of half-sizes (lx, ly): F = R(theta) (I + shear) diag(stretch),
/// theta 45 degrees for a third of them; cpdi2 perturbs the parallelogram's corners.
void randomQuad(std::mt19937_64 &rng, double x, double y, double lx, double ly, bool quad,
                double c[8]) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const double th = U(rng) < 0.33 ? M_PI / 4 : 2 * M_PI * U(rng);
  const double sh = 0.6 * (U(rng) - 0.5), s1 = 0.7 + 0.5 * U(rng), s2 = 0.7 + 0.5 * U(rng);
  const double R[4] = {std::cos(th), -std::sin(th), std::sin(th), std::cos(th)};
  const double A[4] = {s1, sh * s2, 0.0, s2}; // (I + shear) diag(s1, s2)
  double F[4];
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      F[2 * i + j] = R[2 * i] * A[j] + R[2 * i + 1] * A[2 + j];
  const double r1[2] = {F[0] * lx, F[2] * lx}, r2[2] = {F[1] * ly, F[3] * ly};
  static const double sa[4] = {-1, 1, 1, -1}, sb[4] = {-1, -1, 1, 1};
  for (int q = 0; q < 4; ++q) {
    c[2 * q] = x + sa[q] * r1[0] + sb[q] * r2[0];
    c[2 * q + 1] = y + sa[q] * r1[1] + sb[q] * r2[1];
    if (quad) {
      c[2 * q] += 0.2 * std::min(lx, ly) * (2 * U(rng) - 1);
      c[2 * q + 1] += 0.2 * std::min(lx, ly) * (2 * U(rng) - 1);
    }
  }
}

bool insideDomain(const Grid<2> &g, const double *c) {
  const gimp::BoxOf<2> &D = g.levels[0].box;
  const double m = 1e-9 * g.h0();
  for (int q = 0; q < 4; ++q)
    if (c[2 * q] < D[0] + m || c[2 * q] > D[2] - m || c[2 * q + 1] < D[1] + m ||
        c[2 * q + 1] > D[3] - m)
      return false;
  return true;
}

/// Area and centroid of a polygon of four corners.
void centroid(const double *c, double &A, double &cx, double &cy) {
  A = cx = cy = 0;
  for (int q = 0; q < 4; ++q) {
    const int n = (q + 1) % 4;
    const double cr = c[2 * q] * c[2 * n + 1] - c[2 * n] * c[2 * q + 1];
    A += 0.5 * cr;
    cx += (c[2 * q] + c[2 * n]) * cr;
    cy += (c[2 * q + 1] + c[2 * n + 1]) * cr;
  }
  cx /= 6 * A;
  cy /= 6 * A;
}

/// Random quads on every 3-level layout; calls f(grid, corners of n particles, n).
template <class F> void onRandomQuads(bool quad, int perLayout, F &&f) {
  std::mt19937_64 rng(quad ? 2013 : 2011);
  for (const auto &lay : threeLevelLayouts()) {
    const auto gp = makeGrid(sceneOf(lay));
    const Grid<2> &g = *gp;
    Sampler sample(g, rng());
    std::vector<double> c;
    while (static_cast<int>(c.size()) < 8 * perLayout) {
      double x, y, lx, ly, q[8];
      sample.draw(x, y, lx, ly, false, 0.35 * g.h0());
      randomQuad(rng, x, y, lx, ly, quad, q);
      if (insideDomain(g, q)) c.insert(c.end(), q, q + 8);
    }
    f(g, lay.name, c, perLayout);
  }
}

void identities(bool quad) {
  Worst unity, repro, gradSum, gradRepro, node;
  onRandomQuads(
      quad, 300,
      [&](const Grid<2> &g, const std::string &name, const std::vector<double> &c, int n) {
        Stencils s;
        ASSERT_EQ(g.buildCpdiStencils(n, c.data(), s), nullptr) << name;
        const double h0 = g.h0();
        for (int k = 0; k < n; ++k) {
          const double xp = 0.25 * (c[8 * k] + c[8 * k + 2] + c[8 * k + 4] + c[8 * k + 6]);
          const double yp = 0.25 * (c[8 * k + 1] + c[8 * k + 3] + c[8 * k + 5] + c[8 * k + 7]);
          double rel[8], A, cx, cy; // the centroid relative to the corners' mean (no cancellation)
          for (int q = 0; q < 4; ++q) {
            rel[2 * q] = c[8 * k + 2 * q] - xp;
            rel[2 * q + 1] = c[8 * k + 2 * q + 1] - yp;
          }
          centroid(rel, A, cx, cy);
          const double l = std::sqrt(A); // the domain's size, to make gradients dimensionless
          double sw = 0, sx = 0, sy = 0, gx = 0, gy = 0, m[4] = {0, 0, 0, 0}, bad = 0;
          std::map<PetscInt, int> seen;
          for (PetscInt e = s.start[k]; e < s.start[k + 1]; ++e) {
            const PetscInt nd = s.node[e];
            if (nd < 0 || nd >= g.nWindow || !g.active[nd] || seen[nd]++ || s.weight(e) < 0)
              bad = 1;
            const double w = s.weight(e);
            const auto G = s.gradient(e);
            const double rx = g.X[nd] - xp, ry = g.Y[nd] - yp;
            sw += w;
            sx += w * rx;
            sy += w * ry;
            gx += G[0];
            gy += G[1];
            m[0] += G[0] * rx;
            m[1] += G[0] * ry;
            m[2] += G[1] * rx;
            m[3] += G[1] * ry;
          }
          auto where = [&] { return name + " " + at({{"k", double(k)}, {"x", xp}, {"y", yp}}); };
          unity.update(std::abs(sw - 1), where);
          // sum S x_i = the centroid (cpdi: x_p, the parallelogram's centre).
          repro.update(std::hypot(sx - cx, sy - cy) / h0, where);
          gradSum.update(std::hypot(gx, gy) * l, where);
          gradRepro.update(
              std::max({std::abs(m[0] - 1), std::abs(m[1]), std::abs(m[2]), std::abs(m[3] - 1)}),
              where);
          node.update(bad, where);
        }
      });
  EXPECT_WORST_LE(unity, 1e-12);
  EXPECT_WORST_LE(repro, 1e-12);
  EXPECT_WORST_LE(gradSum, 1e-12);
  EXPECT_WORST_LE(gradRepro, 1e-12);
  EXPECT_WORST_LE(node, 0.0);
}

TEST(Cpdi, ApicMomentsAboutTheWeightCentroidReadAnAffineField) {
  // v = b + A x with |b| = 1 m/s far larger than A's 1/s times a cell (a moving body).
  const double A[4] = {0.3, -0.7, 0.5, 0.2}, b[2] = {1.0, -0.6};
  Worst atCentroid, atMean;
  onRandomQuads(
      true, 200,
      [&](const Grid<2> &g, const std::string &name, const std::vector<double> &c, int n) {
        Stencils s;
        ASSERT_EQ(g.buildCpdiStencils(n, c.data(), s), nullptr) << name;
        std::vector<double> xs(2 * g.nWindow), vg(2 * g.nWindow);
        for (PetscInt i = 0; i < g.nWindow; ++i) {
          xs[2 * i] = g.X[i];
          xs[2 * i + 1] = g.Y[i];
          vg[2 * i] = b[0] + A[0] * g.X[i] + A[1] * g.Y[i];
          vg[2 * i + 1] = b[1] + A[2] * g.X[i] + A[3] * g.Y[i];
        }
        std::vector<double> xc(2 * n), mean(2 * n);
        gimp::transfer::weightCentroids<2>(s, n, xs.data(), xc.data());
        for (int k = 0; k < n; ++k)
          for (int d = 0; d < 2; ++d)
            mean[2 * k + d] =
                0.25 * (c[8 * k + d] + c[8 * k + 2 + d] + c[8 * k + 4 + d] + c[8 * k + 6 + d]);
        for (auto *centres : {&xc, &mean}) {
          std::vector<double> v(2 * n), B(4 * n), C(4 * n), x(*centres);
          gimp::transfer::gridToParticlesAffine<2>(s, n, vg.data(), centres->data(), xs.data(), 0.0,
                                                   v.data(), B.data(), x.data());
          gimp::transfer::affineVelocity<2>(s, n, centres->data(), xs.data(), B.data(), C.data());
          for (int k = 0; k < n; ++k) {
            double err = 0;
            for (int q = 0; q < 4; ++q)
              err = std::max(err, std::abs(C[4 * k + q] - A[q]));
            auto where = [&] { return name + " " + at({{"k", double(k)}}); };
            (centres == &xc ? atCentroid : atMean).update(err, where);
            if (centres == &xc) { // v_p is the field at the centroid
              const double vx = b[0] + A[0] * xc[2 * k] + A[1] * xc[2 * k + 1];
              atCentroid.update(std::abs(v[2 * k] - vx), where);
            }
          }
        }
      });
  // Rounding: coordinates of up to ~10 m and |v| ~ 5 m/s against D_p of fine-level particles
  // (~1e-5 m^2) leave ~1e-9 of |A| ~ 1/s.
  EXPECT_WORST_LE(atCentroid, 1e-8);
  // The corners' mean is off the centroid by a few percent of the size: C_p is far off.
  EXPECT_GT(atMean.err, 1e-2);
}

TEST(Cpdi, CornerWeightsAreThePointShapesInOrder) {
  int snapped = 0;
  for (const bool quad : {false, true})
    onRandomQuads(
        quad, 300,
        [&](const Grid<2> &g, const std::string &name, const std::vector<double> &c0, int n) {
          Stencils s;
          ASSERT_EQ(g.buildCpdiStencils(n, c0.data(), s), nullptr) << name;
          for (int k = 0; k < n; ++k)
            gimp::test::expectPointShapeEntries<2>(g, c0.data(), s, k, name);
          // Each quad moved so that its corner k % 4 lies on a level-0 node line (along x or y).
          const double h0 = g.h0();
          for (int k = 0; k < n; ++k) {
            double c[8];
            std::copy(&c0[8 * k], &c0[8 * k + 8], c);
            const int a = (k / 4) % 2;
            const double o = g.levels[0].box[a], x = c[2 * (k % 4) + a];
            const double dx = o + std::round((x - o) / h0) * h0 - x;
            for (int q = 0; q < 4; ++q)
              c[2 * q + a] += dx;
            Stencils t;
            if (!insideDomain(g, c) || g.buildCpdiStencils(1, c, t) != nullptr) continue;
            gimp::test::expectPointShapeEntries<2>(g, c, t, 0, name + " (on a node line)");
            ++snapped;
          }
        });
  EXPECT_GT(snapped, 1000);
}

TEST(Cpdi, ParallelogramIdentities) {
  identities(false);
}
TEST(Cpdi, QuadrilateralIdentities) {
  identities(true);
}

/// Every tent of the grid is smooth (bilinear) over the quad c: no node line or zone end of a node
/// near any corner lies within `gap` of the corners' range.
bool oneCell(const Grid<2> &g, const double *c, double gap) {
  std::vector<std::pair<PetscInt, double>> pts;
  for (int q = 0; q < 4; ++q)
    g.pointShapes(c[2 * q], c[2 * q + 1], pts);
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (int q = 0; q < 4; ++q)
    for (int d = 0; d < 2; ++d) {
      lo[d] = std::min(lo[d], c[2 * q + d] - gap);
      hi[d] = std::max(hi[d], c[2 * q + d] + gap);
    }
  for (const auto &pr : pts) {
    const double *z = &g.zone[4 * pr.first];
    const double X = g.X[pr.first], Y = g.Y[pr.first];
    for (double v : {X - z[0], X, X + z[1]})
      if (v > lo[0] && v < hi[0]) return false;
    for (double v : {Y - z[2], Y, Y + z[3]})
      if (v > lo[1] && v < hi[1]) return false;
  }
  return true;
}

TEST(Cpdi, GradientIsTheTranslationDerivative) {
  {
    const bool quad = false;
    Worst fd;
    long used = 0;
    onRandomQuads(
        quad, 400,
        [&](const Grid<2> &g, const std::string &name, const std::vector<double> &c, int n) {
          const double eps = 1e-6 * g.h0();
          for (int k = 0; k < n; ++k) {
            const double *ck = &c[8 * k];
            if (!oneCell(g, ck, 4 * eps)) continue;
            ++used;
            Stencils s;
            ASSERT_EQ(g.buildCpdiStencils(1, ck, s), nullptr);
            double gmax = 0;
            for (PetscInt e = 0; e < s.start[1]; ++e)
              gmax = std::max(gmax, std::abs(s.gradient(e)[0]) + std::abs(s.gradient(e)[1]));
            for (int d = 0; d < 2; ++d) {
              std::map<PetscInt, double> plus, minus;
              for (int sg : {1, -1}) {
                double m[8];
                for (int q = 0; q < 8; ++q)
                  m[q] = ck[q] + (q % 2 == d ? sg * eps : 0.0);
                Stencils t;
                ASSERT_EQ(g.buildCpdiStencils(1, m, t), nullptr);
                for (PetscInt e = 0; e < t.start[1]; ++e)
                  (sg > 0 ? plus : minus)[t.node[e]] = t.weight(e);
              }
              std::map<PetscInt, double> grad;
              for (PetscInt e = 0; e < s.start[1]; ++e)
                grad[s.node[e]] = s.gradient(e)[d];
              for (const auto &pr : plus)
                grad.emplace(pr.first, 0.0);
              for (const auto &pr : minus)
                grad.emplace(pr.first, 0.0);
              for (const auto &[nd, gv] : grad) {
                const double f = (plus[nd] - minus[nd]) / (2 * eps);
                fd.update(std::abs(f - gv) / gmax, [&] {
                  return name + " " + at({{"k", double(k)}, {"node", double(nd)}});
                });
              }
            }
          }
        });
    // Central differences of a piecewise-linear function away from its kinks: round-off only
    // (weights of order 1 over 2 eps = 2e-6 h0).
    EXPECT_WORST_LE(fd, 1e-7);
    EXPECT_GT(used, 500);
  }
}

TEST(Cpdi, RotatedSquareInOneCellAveragesOverItsTrueArea) {
  // Squares rotated by 45 degrees (and random angles) inside one level-0 cell of a uniform
  // grid, where every N_i is bilinear: for a rotation the parallelogram map makes N_i a
  // polynomial whose average the corner values give exactly. The reference is a brute-force
  // midpoint rule of N_i over the rotated square (M x M sub-squares).
  const auto gp = makeGrid(sceneOf({"uniform", 6, 5, {}}));
  const Grid<2> &g = *gp;
  const double h = g.h0();
  std::mt19937_64 rng(45);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  Worst cpdi;
  const int M = 400;
  for (int t = 0; t < 40; ++t) {
    const double th = t % 2 ? M_PI / 4 : 2 * M_PI * U(rng), l = h * (0.1 + 0.15 * U(rng));
    const double r = l * (std::abs(std::cos(th)) + std::abs(std::sin(th)));
    const gimp::BoxOf<2> &D = g.levels[0].box;
    const double i = 2 + std::floor(U(rng) * 2), j = 2 + std::floor(U(rng) * 2);
    const double x = D[0] + (i + r / h + U(rng) * (1 - 2 * r / h)) * h;
    const double y = D[1] + (j + r / h + U(rng) * (1 - 2 * r / h)) * h;
    const double e1[2] = {l * std::cos(th), l * std::sin(th)}, e2[2] = {-e1[1], e1[0]};
    double c[8];
    static const double sa[4] = {-1, 1, 1, -1}, sb[4] = {-1, -1, 1, 1};
    for (int q = 0; q < 4; ++q)
      for (int d = 0; d < 2; ++d)
        c[2 * q + d] = (d ? y : x) + sa[q] * e1[d] + sb[q] * e2[d];
    Stencils s;
    ASSERT_EQ(g.buildCpdiStencils(1, c, s), nullptr);
    std::map<PetscInt, double> ref;
    std::vector<std::pair<PetscInt, double>> pts;
    for (int a = 0; a < M; ++a)
      for (int b = 0; b < M; ++b) {
        const double xi = -1 + (2 * a + 1.0) / M, eta = -1 + (2 * b + 1.0) / M;
        pts.clear();
        g.pointShapes(x + xi * e1[0] + eta * e2[0], y + xi * e1[1] + eta * e2[1], pts);
        for (const auto &[nd, N] : pts)
          ref[nd] += N / (double(M) * M);
      }
    for (PetscInt e = 0; e < s.start[1]; ++e)
      cpdi.update(std::abs(s.weight(e) - ref[s.node[e]]), [&] {
        return at({{"theta", th}, {"x", x}, {"y", y}, {"l", l}});
      });
  }
  // The midpoint rule's own error is below (1/M)^2 of N's second derivatives times l^2.
  EXPECT_WORST_LE(cpdi, 1e-6);
}

/// Whether the rectangle [x0, x1] x [y0, y1] meets the square of centre (x, y) and half-axes e1,
/// e2 (perpendicular, equal length): separating axes x, y, e1, e2.
bool meets(const double R[4], double x, double y, const double e1[2], const double e2[2]) {
  const double ex = std::abs(e1[0]) + std::abs(e2[0]), ey = std::abs(e1[1]) + std::abs(e2[1]);
  if (x + ex <= R[0] || x - ex >= R[1] || y + ey <= R[2] || y - ey >= R[3]) return false;
  for (const double *a : {e1, e2}) {
    const double la = std::hypot(a[0], a[1]);
    double lo = 1e300, hi = -1e300;
    for (double px : {R[0], R[1]})
      for (double py : {R[2], R[3]}) {
        const double s = ((px - x) * a[0] + (py - y) * a[1]) / la;
        lo = std::min(lo, s);
        hi = std::max(hi, s);
      }
    if (hi <= -la || lo >= la) return false;
  }
  return true;
}

TEST(Cpdi, RotatedSquareWeightsLiveOnItsTrueArea) {
  const auto gp = makeGrid(sceneOf({"uniform", 6, 5, {}}));
  const Grid<2> &g = *gp;
  const double h = g.h0();
  const gimp::BoxOf<2> &D = g.levels[0].box;
  std::mt19937_64 rng(4545);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  long cpdiOutside = 0, boxOutside = 0;
  for (int t = 0; t < 2000; ++t) {
    const double th = M_PI / 4, l = h * (0.2 + 0.15 * U(rng));
    const double x = D[0] + (1.5 + 3 * U(rng)) * h, y = D[1] + (1.5 + 2 * U(rng)) * h;
    const double e1[2] = {l * std::cos(th), l * std::sin(th)}, e2[2] = {-e1[1], e1[0]};
    double c[8];
    static const double sa[4] = {-1, 1, 1, -1}, sb[4] = {-1, -1, 1, 1};
    for (int q = 0; q < 4; ++q)
      for (int d = 0; d < 2; ++d)
        c[2 * q + d] = (d ? y : x) + sa[q] * e1[d] + sb[q] * e2[d];
    Stencils s, box;
    ASSERT_EQ(g.buildCpdiStencils(1, c, s), nullptr);
    const double r = l * std::sqrt(2.0), pos[2] = {x, y}, half[2] = {r, r}; // the corners' box
    ASSERT_TRUE(g.buildStencils(1, pos, half, box));
    auto outside = [&](const Stencils &st) {
      long n = 0;
      for (PetscInt e = 0; e < st.start[1]; ++e) {
        const PetscInt nd = st.node[e];
        const double *z = &g.zone[4 * nd];
        const double R[4] = {g.X[nd] - z[0], g.X[nd] + z[1], g.Y[nd] - z[2], g.Y[nd] + z[3]};
        n += st.weight(e) > 0 && !meets(R, x, y, e1, e2);
      }
      return n;
    };
    cpdiOutside += outside(s);
    boxOutside += outside(box);
  }
  std::printf("  nodes weighted outside the true square: cpdi %ld, axis-aligned box %ld\n",
              cpdiOutside, boxOutside);
  EXPECT_EQ(cpdiOutside, 0);
  EXPECT_GT(boxOutside, 100);
}

TEST(Cpdi, CornerOutsideTheGridOrInvertedQuadIsReported) {
  const auto gp = makeGrid(sceneOf({"uniform", 6, 5, {}}));
  const Grid<2> &g = *gp;
  const gimp::BoxOf<2> &D = g.levels[0].box;
  const double h = g.h0(), x = D[0] + 0.1 * h, y = D[1] + 2.5 * h;
  const double out[8] = {x - 0.2 * h, y - 0.2 * h, x + 0.2 * h, y - 0.2 * h,
                         x + 0.2 * h, y + 0.2 * h, x - 0.2 * h, y + 0.2 * h};
  Stencils s;
  const char *why = g.buildCpdiStencils(1, out, s);
  ASSERT_NE(why, nullptr);
  EXPECT_NE(std::string(why).find("outside the grid"), std::string::npos) << why;
  const double xi = D[0] + 2.5 * h;
  const double inv[8] = {xi - 0.2 * h, y - 0.2 * h, xi - 0.2 * h, y + 0.2 * h,
                         xi + 0.2 * h, y + 0.2 * h, xi + 0.2 * h, y - 0.2 * h}; // clockwise
  why = g.buildCpdiStencils(1, inv, s);
  ASSERT_NE(why, nullptr);
  EXPECT_NE(std::string(why).find("inverted"), std::string::npos) << why;
}

TEST(Cpdi, RotatedPatchUnderUniformStressIsInEquilibrium) {
  // 3 levels: the block straddles the level boxes, so interior nodes include transition nodes.
  const auto gp = makeGrid(sceneOf({"3 levels", 10, 8, {{2, 2, 8, 6, 2}, {3.5, 3, 6, 5, 4}}}));
  const Grid<2> &g = *gp;
  const gimp::BoxOf<2> &D = g.levels[0].box;
  const double h = g.h0(), a = 0.3 * h, th = M_PI / 4;
  const double ox = D[0] + 5.0 * h, oy = D[1] + 1.2 * h; // the block's lowest corner
  const double u[2] = {a * std::cos(th), a * std::sin(th)}, v[2] = {-u[1], u[0]};
  const int n = 12; // n x n particles, a block of side n a
  std::vector<double> c, xs, ls, V, sig;
  const double stress[3] = {3.0, -2.0, 1.25}; // xx, yy, xy (the stored order)
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      static const double si[4] = {0, 1, 1, 0}, sj[4] = {0, 0, 1, 1};
      for (int q = 0; q < 4; ++q) {
        c.push_back(ox + (i + si[q]) * u[0] + (j + sj[q]) * v[0]);
        c.push_back(oy + (i + si[q]) * u[1] + (j + sj[q]) * v[1]);
      }
      xs.push_back(ox + (i + 0.5) * u[0] + (j + 0.5) * v[0]);
      xs.push_back(oy + (i + 0.5) * u[1] + (j + 0.5) * v[1]);
      ls.push_back(a / std::sqrt(2.0)); // the corners' axis-aligned box (corner tracking)
      ls.push_back(a / std::sqrt(2.0));
      V.push_back(a * a);
      sig.insert(sig.end(), stress, stress + 3);
    }
  const PetscInt np = n * n;
  // A node is interior when its support lies inside the block (in the block's frame).
  auto interior = [&](PetscInt nd) {
    const double *z = &g.zone[4 * nd];
    for (double px : {g.X[nd] - z[0], g.X[nd] + z[1]})
      for (double py : {g.Y[nd] - z[2], g.Y[nd] + z[3]}) {
        const double s = ((px - ox) * u[0] + (py - oy) * u[1]) / (a * a);
        const double t = ((px - ox) * v[0] + (py - oy) * v[1]) / (a * a);
        if (!(s > 0 && s < n && t > 0 && t < n)) return false;
      }
    return true;
  };
  auto worstInterior = [&](const Stencils &st, long &count) {
    std::vector<double> f(2 * g.nWindow, 0.0);
    gimp::transfer::internalForce<2>(st, np, V.data(), sig.data(), f.data());
    double worst = 0, fx = 0, fy = 0;
    count = 0;
    for (PetscInt nd = 0; nd < g.nWindow; ++nd) {
      fx += f[2 * nd];
      fy += f[2 * nd + 1];
      if (!g.active[nd] || !interior(nd)) continue;
      ++count;
      worst = std::max(worst, std::hypot(f[2 * nd], f[2 * nd + 1]));
    }
    EXPECT_LE(std::hypot(fx, fy), 1e-13 * 3.0 * n * a); // the block's forces balance
    return worst / (3.0 * a); // relative to a particle's edge force, |sigma| a
  };
  Stencils cpdi, box;
  ASSERT_EQ(g.buildCpdiStencils(np, c.data(), cpdi), nullptr);
  ASSERT_TRUE(g.buildStencils(np, xs.data(), ls.data(), box));
  long nc = 0, nb = 0;
  const double ec = worstInterior(cpdi, nc), eb = worstInterior(box, nb);
  std::printf("  interior nodes %ld: largest |f| / (|sigma| a): cpdi %.3g, corners' boxes %.3g\n",
              nc, ec, eb);
  EXPECT_GT(nc, 50);
  EXPECT_LE(ec, 1e-12);
  EXPECT_GT(eb, 1e-3);
}

} // namespace
