// Unit tests of the 3D crack front's auxiliary fields (frontField in include/gimp/cracks/
// williams.hpp) and of the equivalent domain integrals along a front (include/gimp/cracks/
// front.hpp), on small-strain linear elastic fields carried by particles on a lattice.
//
//   1. The auxiliary fields: the analytic gradient against central differences of the
//      displacement, the stress is Hooke's law of that gradient (3D, lambda and mu), the stress is
//      in equilibrium (central differences of the stress), the faces are free, modes 1 and 2 are
//      the 2D plane-strain fields.
//   2. A straight front: an exact mixed field K = (1, 0.5, 0.3) MPa m^0.5 around it, the whole
//      setup turned to an arbitrary frame: each K and G = (K_I^2 + K_II^2) / E' + K_III^2 / (2 mu)
//      within 0.24 % at R = L = 5 h, at a front point in the middle of one front edge and at one
//      next to the end of a front edge followed by a collinear one; with the lattice on the
//      global axes instead (across the front), G within 0.25 % and the K's within 2.3 %.
//   1b. The curvature terms (curvatureIntegrand): on a circular front, against central
//      differences of the fields the circle carries, every mode; zero on a straight front.
//   3. A circular front (64-gon, radius a = 40 h, the crack inside): the local field of the
//      nearest point of the circle at every particle, constant K's. That field is not an elastic
//      solution (the curvature terms assume one), so its J depends on the domain, linearly in
//      R / a: at R = L = 5 h, G within 3.4 %, K_I 0.5 %, K_II 6.2 %, K_III 5.2 % in either frame of
//      the auxiliary fields (P's, or the nearest front point's with the curvature terms); on a =
//      80 h, extrapolated from R = 10 h and 20 h to R = 0, every measure within 1 %.
//   4. A uniform stress that leaves the faces free (s11, s33, s13 in the front's frame) gives K
//      within 0.25 % of s0 sqrt(pi R) of 0.
//   5. measureFronts: every front point of every crack, as addFrontIntegrals and finishFront.
//   6. A symmetry plane: a front that ends on it, with half the particles and their mirror images,
//      gives the whole body's measures to round-off; a plane the crack lies in gives no image.
#include "gimp/cracks/front.hpp"
#include "gimp/cracks/front_fields.hpp"

#include "../src/cracks/front_chain.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

namespace {

using gimp::CrackSurface;
using gimp::Material;
using gimp::cracks::AuxFrame;
using gimp::cracks::frontDisplacement;
using gimp::cracks::frontField;
using gimp::cracks::FrontPoint;
using gimp::cracks::TipElastic;
using P3 = std::array<double, 3>;
namespace chain = gimp::cracks::chain;

constexpr double kPi = 3.141592653589793;

Material material() {
  Material m;
  m.E = 70e9;
  m.nu = 0.3;
  m.mu = m.E / (2 * (1 + m.nu));
  m.lambda = m.E * m.nu / ((1 + m.nu) * (1 - 2 * m.nu));
  return m;
}

/// The full 3x3 displacement gradient of unit mode `mode` at local (x1, x2) by central
/// differences (the field does not vary along x3).
void gradientFD(int mode, double x1, double x2, const TipElastic &e, double g[3][3]) {
  const double d = 1e-6 * std::hypot(x1, x2);
  for (int j = 0; j < 3; ++j) {
    double up[3] = {0, 0, 0}, um[3] = {0, 0, 0};
    if (j < 2) {
      const double px = x1 + (j == 0 ? d : 0), py = x2 + (j == 1 ? d : 0);
      const double mx = x1 - (j == 0 ? d : 0), my = x2 - (j == 1 ? d : 0);
      frontDisplacement(mode, std::hypot(px, py), std::atan2(py, px), e, up);
      frontDisplacement(mode, std::hypot(mx, my), std::atan2(my, mx), e, um);
    }
    for (int i = 0; i < 3; ++i)
      g[i][j] = (up[i] - um[i]) / (2 * d);
  }
}

TEST(FrontField, GradientAndStressAreThoseOfTheDisplacement) {
  const Material m = material();
  const TipElastic e = gimp::cracks::frontElastic(m);
  for (int mode = 1; mode <= 3; ++mode)
    for (double th = -3.0; th <= 3.0; th += 0.25) {
      const double r = 2e-3, x1 = r * std::cos(th), x2 = r * std::sin(th);
      double s[3][3], g[3][3], gd[3][3];
      frontField(mode, r, th, e, s, g);
      gradientFD(mode, x1, x2, e, gd);
      const double gs = 1 / (e.mu * std::sqrt(2 * kPi * r)), ss = 1 / std::sqrt(2 * kPi * r);
      double tr = 0;
      for (int i = 0; i < 3; ++i)
        tr += gd[i][i];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          EXPECT_NEAR(g[i][j], gd[i][j], 1e-6 * gs) << "mode " << mode << " theta " << th;
          const double hooke = (i == j ? m.lambda * tr : 0.0) + m.mu * (gd[i][j] + gd[j][i]);
          EXPECT_NEAR(s[i][j], hooke, 1e-6 * ss) << "mode " << mode << " theta " << th;
        }
    }
}

TEST(FrontField, StressIsInEquilibriumAndFacesAreFree) {
  const TipElastic e = gimp::cracks::frontElastic(material());
  for (int mode = 1; mode <= 3; ++mode)
    for (double th = -2.9; th <= 2.9; th += 0.3) {
      const double r = 1e-3, x1 = r * std::cos(th), x2 = r * std::sin(th), d = 1e-5 * r;
      double sp[3][3], sm[3][3], g[3][3], div[3] = {0, 0, 0};
      for (int j = 0; j < 2; ++j) {
        const double px = x1 + (j == 0 ? d : 0), py = x2 + (j == 1 ? d : 0);
        const double mx = x1 - (j == 0 ? d : 0), my = x2 - (j == 1 ? d : 0);
        frontField(mode, std::hypot(px, py), std::atan2(py, px), e, sp, g);
        frontField(mode, std::hypot(mx, my), std::atan2(my, mx), e, sm, g);
        for (int i = 0; i < 3; ++i)
          div[i] += (sp[i][j] - sm[i][j]) / (2 * d);
      }
      const double scale = 1 / (r * std::sqrt(2 * kPi * r)); // |grad s| ~ s / r
      for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(div[i], 0.0, 1e-6 * scale) << "mode " << mode << " theta " << th;
    }
  for (int mode = 1; mode <= 3; ++mode)
    for (double th : {kPi, -kPi}) {
      double s[3][3], g[3][3];
      frontField(mode, 1e-3, th, e, s, g);
      for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(s[i][1], 0.0, 1e-12 / std::sqrt(2e-3 * kPi));
    }
  // The tearing: u3(pi) - u3(-pi) = 4 / mu sqrt(r / 2 pi) for K_III = 1.
  double up[3], dn[3];
  frontDisplacement(3, 1e-3, kPi, e, up);
  frontDisplacement(3, 1e-3, -kPi, e, dn);
  EXPECT_NEAR(up[2] - dn[2], 4 / e.mu * std::sqrt(1e-3 / (2 * kPi)), 1e-12 * up[2]);
}

TEST(FrontField, ModesOneAndTwoAreThePlaneStrainFields) {
  const Material m = material();
  const TipElastic e = gimp::cracks::frontElastic(m);
  for (int mode = 1; mode <= 2; ++mode)
    for (double th = -3.0; th <= 3.0; th += 0.5) {
      double s[3][3], g[3][3], s2[3], du[2], u[3], u2[2];
      frontField(mode, 1e-3, th, e, s, g);
      gimp::cracks::williamsField(mode, 1e-3, th, e, s2, du);
      frontDisplacement(mode, 1e-3, th, e, u);
      gimp::cracks::williamsDisplacement(mode, 1e-3, th, e, u2);
      EXPECT_DOUBLE_EQ(s[0][0], s2[0]);
      EXPECT_DOUBLE_EQ(s[1][1], s2[1]);
      EXPECT_DOUBLE_EQ(s[0][1], s2[2]);
      EXPECT_NEAR(s[2][2], m.nu * (s2[0] + s2[1]), 1e-12 * std::fabs(s2[0]) + 1e-12);
      EXPECT_NEAR(g[0][0], du[0], 1e-12 * std::fabs(du[0]));
      EXPECT_NEAR(g[1][0], du[1], 1e-12 * std::fabs(du[1]));
      EXPECT_DOUBLE_EQ(u[0], u2[0]);
      EXPECT_DOUBLE_EQ(u[1], u2[1]);
      EXPECT_EQ(u[2], 0.0);
    }
}

/// A rigid placement: global = B^T local + c, B's rows the local axes in global components.
struct Placement {
  double B[3][3];
  P3 c;
  P3 toGlobal(const P3 &l) const {
    P3 g = c;
    for (int i = 0; i < 3; ++i)
      for (int a = 0; a < 3; ++a)
        g[i] += B[a][i] * l[a];
    return g;
  }
  /// A local tensor T (local components) in global components.
  void tensorToGlobal(const double T[3][3], double out[3][3]) const {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        out[i][j] = 0;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b)
            out[i][j] += B[a][i] * T[a][b] * B[b][j];
      }
  }
};

/// Identity, or a rotation by Euler angles (z, x, z) 0.7, 1.1, -0.4 and a shift.
Placement placement(bool turned) {
  Placement p{};
  if (!turned) {
    for (int i = 0; i < 3; ++i)
      p.B[i][i] = 1;
    return p;
  }
  const double a = 0.7, b = 1.1, g = -0.4;
  const double ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b),
               cg = std::cos(g), sg = std::sin(g);
  const double Z1[3][3] = {{ca, -sa, 0}, {sa, ca, 0}, {0, 0, 1}};
  const double X[3][3] = {{1, 0, 0}, {0, cb, -sb}, {0, sb, cb}};
  const double Z2[3][3] = {{cg, -sg, 0}, {sg, cg, 0}, {0, 0, 1}};
  double T[3][3] = {};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        T[i][j] += Z1[i][k] * X[k][j];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        p.B[i][j] += T[i][k] * Z2[k][j];
  p.c = {0.013, -0.021, 0.034};
  return p;
}

/// Particles of a lattice of spacing h (offset by h / 2) in local axes, or in the axes of
/// `lattice` when given (lo and hi then in its axes), carrying a stress s and displacement gradient
/// g given in local components at local positions.
struct Particles {
  std::vector<double> x, X0, m, V0, V, l, F, s;
  gimp::ParticleView<3> view;
  template <class Field>
  Particles(const Placement &pl, const P3 &lo, const P3 &hi, double h, Field field,
            const Placement *lattice = nullptr) {
    const int n[3] = {static_cast<int>(std::round((hi[0] - lo[0]) / h)),
                      static_cast<int>(std::round((hi[1] - lo[1]) / h)),
                      static_cast<int>(std::round((hi[2] - lo[2]) / h))};
    for (int i = 0; i < n[0]; ++i)
      for (int j = 0; j < n[1]; ++j)
        for (int k = 0; k < n[2]; ++k) {
          const P3 at = {lo[0] + (i + 0.5) * h, lo[1] + (j + 0.5) * h, lo[2] + (k + 0.5) * h};
          const P3 xg = (lattice ? *lattice : pl).toGlobal(at);
          P3 loc{};
          for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
              loc[a] += pl.B[a][b] * (xg[b] - pl.c[b]);
          double sl[3][3], gl[3][3], sg[3][3], gg[3][3];
          field(loc, sl, gl);
          pl.tensorToGlobal(sl, sg);
          pl.tensorToGlobal(gl, gg);
          x.insert(x.end(), xg.begin(), xg.end());
          X0.insert(X0.end(), xg.begin(), xg.end());
          m.push_back(1.0);
          V0.push_back(h * h * h);
          V.push_back(h * h * h);
          l.insert(l.end(), {h / 2, h / 2, h / 2});
          for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
              F.push_back((a == b ? 1.0 : 0.0) + gg[a][b]);
          s.insert(s.end(), {sg[0][0], sg[1][1], sg[2][2], sg[1][2], sg[0][2], sg[0][1]});
        }
    view.n = static_cast<PetscInt>(m.size());
    view.x = x.data();
    view.X0 = X0.data();
    view.m = m.data();
    view.V0 = V0.data();
    view.V = V.data();
    view.l = l.data();
    view.F = F.data();
    view.s = s.data();
  }
};

/// The crack polygon of local points, placed; front edges those with both ends at local x1 = 0
/// (straight) or all (circle).
CrackSurface placedCrack(const Placement &pl, const std::vector<P3> &local, bool allFront) {
  std::vector<P3> pts;
  for (const P3 &q : local)
    pts.push_back(pl.toGlobal(q));
  const double up[3] = {pl.B[1][0], pl.B[1][1], pl.B[1][2]};
  CrackSurface c = gimp::cracks::makeSurface(pts, up);
  const size_t m = c.points.size();
  c.front.assign(m, allFront ? 1 : 0);
  if (!allFront)
    for (size_t e = 0; e < m; ++e) {
      const P3 &a = c.points[e], &b = c.points[(e + 1) % m];
      double la = 0, lb = 0; // local x1 of both ends
      for (int i = 0; i < 3; ++i) {
        la += pl.B[0][i] * (a[i] - pl.c[i]);
        lb += pl.B[0][i] * (b[i] - pl.c[i]);
      }
      c.front[e] = std::fabs(la) < 1e-12 && std::fabs(lb) < 1e-12;
    }
  return c;
}

/// K_m times the unit fields at local (x1, x2) of a front frame, summed.
void mixedField(const double K[3], const TipElastic &e, double x1, double x2, double s[3][3],
                double g[3][3]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      s[i][j] = g[i][j] = 0;
  for (int mode = 1; mode <= 3; ++mode) {
    double sm[3][3], gm[3][3];
    frontField(mode, std::hypot(x1, x2), std::atan2(x2, x1), e, sm, gm);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        s[i][j] += K[mode - 1] * sm[i][j];
        g[i][j] += K[mode - 1] * gm[i][j];
      }
  }
}

/// Relative errors of (G, K_I, K_II, K_III) at front point f against K.
std::array<double, 4> errors(const Material &mat, const Particles &p, const CrackSurface &c,
                             const FrontPoint &f, double R, double L, const double K[3],
                             AuxFrame aux) {
  double sums[4] = {0, 0, 0, 0};
  gimp::cracks::addFrontIntegrals(mat, p.view, c, f, R, L, sums, aux);
  const gimp::cracks::FrontMeasure fm = gimp::cracks::finishFront(mat, c, f, R, L, sums);
  const double Ep = mat.E / (1 - mat.nu * mat.nu);
  const double G = (K[0] * K[0] + K[1] * K[1]) / Ep + K[2] * K[2] / (2 * mat.mu);
  return {fm.G / G - 1, fm.KI / K[0] - 1, fm.KII / K[1] - 1, fm.KIII / K[2] - 1};
}

TEST(FrontField, CurvatureTermsAreThoseOfTheFieldsOnACircularFront) {
  // The fields carried by a circular front of radius a (the plane z = 0, the crack inside): at x,
  // the frame of the circle's nearest point (e1 radial, e2 = z, e3 = e1 x e2) at local (x1, x2) =
  // (r_xy - a, z). Their Cartesian derivatives by central differences of the whole map against
  // curvatureIntegrand with the circle's curvature (c = t / a), for an arbitrary stress and
  // displacement gradient, every mode, points ahead of and behind the front, above and below it;
  // and on a straight front (c = 0) the terms vanish.
  const Material mat = material();
  const TipElastic el = gimp::cracks::frontElastic(mat);
  const double a = 10e-3;
  const auto fields = [&](const P3 &x, int mode, double S[3][3], double G[3][3]) {
    const double rxy = std::hypot(x[0], x[1]);
    const P3 e1 = {x[0] / rxy, x[1] / rxy, 0}, e2 = {0, 0, 1}, e3 = {e1[1], -e1[0], 0};
    double SS[3][3][3], GG[3][3][3];
    gimp::cracks::frontAuxGlobal(el, rxy - a, x[2], e1, e2, e3, SS, GG);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        S[i][j] = SS[mode - 1][i][j];
        G[i][j] = GG[mode - 1][i][j];
      }
  };
  gimp::Tensor<3> sg, H;
  sg << 3.0, 0.7, -1.1, 0.7, -2.0, 0.4, -1.1, 0.4, 1.5;
  H << 0.3, -0.8, 0.5, 0.2, 1.1, -0.6, 0.9, 0.1, -0.4;
  for (double phi : {0.3, 2.0, -2.6})
    for (double x1 : {2e-3, -3e-3})
      for (double x2 : {1.5e-3, -0.7e-3}) {
        const double rxy = a + x1;
        const P3 x = {rxy * std::cos(phi), rxy * std::sin(phi), x2};
        const P3 e[3] = {
            {std::cos(phi), std::sin(phi), 0}, {0, 0, 1}, {std::sin(phi), -std::cos(phi), 0}};
        double curv[3][3], t[3];
        const P3 tan = {-std::sin(phi), std::cos(phi), 0};
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            curv[i][j] = tan[static_cast<size_t>(i)] * tan[static_cast<size_t>(j)] / a;
        ASSERT_TRUE(gimp::cracks::curvatureIntegrand(el, x1, x2, e, curv, sg, H, t));
        for (int mode = 1; mode <= 3; ++mode) {
          // dS[i][k][j], dG[i][k][j]: d/dx_j by central differences of the map.
          double dS[3][3][3], dG[3][3][3];
          const double d = 1e-7;
          for (int j = 0; j < 3; ++j) {
            P3 xp = x, xm = x;
            xp[static_cast<size_t>(j)] += d;
            xm[static_cast<size_t>(j)] -= d;
            double Sp[3][3], Gp[3][3], Sm[3][3], Gm[3][3];
            fields(xp, mode, Sp, Gp);
            fields(xm, mode, Sm, Gm);
            for (int i = 0; i < 3; ++i)
              for (int k = 0; k < 3; ++k) {
                dS[i][k][j] = (Sp[i][k] - Sm[i][k]) / (2 * d);
                dG[i][k][j] = (Gp[i][k] - Gm[i][k]) / (2 * d);
              }
          }
          double ref = 0, scale = 0;
          for (int k = 0; k < 3; ++k)
            for (int i = 0; i < 3; ++i) {
              const double divS = dS[i][0][0] + dS[i][1][1] + dS[i][2][2];
              double tk = divS * H(i, k);
              scale += std::fabs(divS * H(i, k));
              for (int j = 0; j < 3; ++j) {
                tk += sg(i, j) * (dG[i][k][j] - dG[i][j][k]);
                scale += std::fabs(sg(i, j) * dG[i][k][j]);
              }
              ref += e[0][static_cast<size_t>(k)] * tk;
            }
          EXPECT_NEAR(t[mode - 1], ref, 1e-6 * scale)
              << "mode " << mode << " phi " << phi << " x1 " << x1 << " x2 " << x2;
          EXPECT_GT(std::fabs(ref), 1e-3 * scale) << "mode " << mode; // the terms are not zero
        }
        double zero[3][3] = {}, t0[3];
        ASSERT_TRUE(gimp::cracks::curvatureIntegrand(el, x1, x2, e, zero, sg, H, t0));
        for (int m = 0; m < 3; ++m)
          EXPECT_NEAR(t0[m], 0.0, 1e-8 * std::fabs(t[m]) + 1e-9) << "straight, mode " << m + 1;
      }
}

constexpr double kH = 1e-3;
const double kK[3] = {1e6, 0.5e6, 0.3e6};

TEST(FrontIntegrals, StraightFrontRecoversTheKs) {
  const Material mat = material();
  const TipElastic e = gimp::cracks::frontElastic(mat);
  const double R = 5 * kH, L = 5 * kH, Z = 20 * kH;
  for (bool turned : {false, true}) {
    const Placement pl = placement(turned);
    // The crack x1 < 0 in the plane x2 = 0; its front x1 = 0 runs along -x3 (a = x1, n = x2).
    const CrackSurface c =
        placedCrack(pl, {{-30 * kH, 0, -Z}, {0, 0, -Z}, {0, 0, Z}, {-30 * kH, 0, Z}}, false);
    const std::vector<FrontPoint> fp = gimp::cracks::frontPoints(c, 2 * Z);
    ASSERT_EQ(fp.size(), 1u);
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(fp[0].a[i], pl.B[0][i], 1e-12);
    EXPECT_NEAR(gimp::cracks::frontArea(c, fp[0], L), 16 * L / 15, 1e-12 * L);
    // The lattice along the front's axes, and (turned) along the global axes.
    for (int grid = 0; grid < (turned ? 2 : 1); ++grid) {
      const Placement axes = placement(false);
      const double w = R + L + 2 * kH;
      const Particles p =
          grid == 0 ? Particles(pl, {-R - kH, -R - kH, -L - kH}, {R + kH, R + kH, L + kH}, kH,
                                [&](const P3 &x, double s[3][3], double g[3][3]) {
                                  mixedField(kK, e, x[0], x[1], s, g);
                                })
                    : Particles(
                          pl, {pl.c[0] - w, pl.c[1] - w, pl.c[2] - w},
                          {pl.c[0] + w, pl.c[1] + w, pl.c[2] + w}, kH,
                          [&](const P3 &x, double s[3][3], double g[3][3]) {
                            mixedField(kK, e, x[0], x[1], s, g);
                          },
                          &axes);
      const auto err = errors(mat, p, c, fp[0], R, L, kK, AuxFrame::Point);
      // On a straight front both frames of the auxiliary fields are the same.
      const auto errNear = errors(mat, p, c, fp[0], R, L, kK, AuxFrame::Nearest);
      for (size_t q = 0; q < 4; ++q)
        EXPECT_NEAR(errNear[q], err[q], 1e-9);
      std::printf("straight front%s, R = L = 5 h: G %+.4f %%, KI %+.4f %%, KII %+.4f %%, KIII "
                  "%+.4f %%\n",
                  turned ? (grid ? " (turned, lattice on the axes)" : " (turned with its lattice)")
                         : "",
                  100 * err[0], 100 * err[1], 100 * err[2], 100 * err[3]);
      // A lattice across the front samples the singular cross terms of the modes (the q_s' t
      // part of grad q, of order K^2 / (mu rho) at the front) at particles as near the front as
      // the lattice happens to put them: K's within 1 % when the lattice follows the front, 3 %
      // when not (G within 0.25 % either way).
      for (int q = 0; q < 4; ++q)
        EXPECT_LT(std::fabs(err[q]), grid == 0 ? 1e-2 : 3e-2) << "measure " << q;
    }
  }
}

TEST(FrontIntegrals, StraightFrontAcrossTwoCollinearEdges) {
  const Material mat = material();
  const TipElastic e = gimp::cracks::frontElastic(mat);
  const double R = 5 * kH, L = 5 * kH, Z = 20 * kH;
  const Placement pl = placement(true);
  // Two collinear front edges, x3 from Z to 0 and from 0 to -Z.
  const CrackSurface c = placedCrack(
      pl, {{-30 * kH, 0, -Z}, {0, 0, -Z}, {0, 0, 0}, {0, 0, Z}, {-30 * kH, 0, Z}}, false);
  const std::vector<FrontPoint> fp = gimp::cracks::frontPoints(c, 4 * kH);
  ASSERT_EQ(fp.size(), 10u);
  // The last point of the first front edge (along t = -x3): local x3 = 2 h, its domain reaching
  // x3 = -3 h on the second edge.
  int at = -1;
  for (size_t q = 0; q < fp.size(); ++q) {
    double x3 = 0;
    for (int i = 0; i < 3; ++i)
      x3 += pl.B[2][i] * (fp[q].x[i] - pl.c[i]);
    if (std::fabs(x3 - 2 * kH) < 1e-9) at = static_cast<int>(q);
  }
  ASSERT_GE(at, 0);
  const FrontPoint &f = fp[static_cast<size_t>(at)];
  EXPECT_NEAR(gimp::cracks::frontArea(c, f, L), 16 * L / 15, 1e-12 * L);
  const Particles p(
      pl, {-R - kH, -R - kH, 2 * kH - L - kH}, {R + kH, R + kH, 2 * kH + L + kH}, kH,
      [&](const P3 &x, double s[3][3], double g[3][3]) { mixedField(kK, e, x[0], x[1], s, g); });
  const auto err = errors(mat, p, c, f, R, L, kK, AuxFrame::Point);
  // On a straight front both frames of the auxiliary fields are the same.
  const auto errNear = errors(mat, p, c, f, R, L, kK, AuxFrame::Nearest);
  for (size_t q = 0; q < 4; ++q)
    EXPECT_NEAR(errNear[q], err[q], 1e-9);
  std::printf("two collinear edges, R = L = 5 h: G %+.4f %%, KI %+.4f %%, KII %+.4f %%, KIII "
              "%+.4f %%\n",
              100 * err[0], 100 * err[1], 100 * err[2], 100 * err[3]);
  for (int q = 0; q < 4; ++q)
    EXPECT_LT(std::fabs(err[q]), 1e-2) << "measure " << q;
}

/// A local tensor T given in the frame of rows E (E[a] the axis a in local components) in local
/// components: E^T T E.
void fromFrame(const double E[3][3], const double T[3][3], double out[3][3]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      out[i][j] = 0;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          out[i][j] += E[a][i] * T[a][b] * E[b][j];
    }
}

/// The local front field of constant K's about the circle x1^2 + x3^2 = ac^2 in the plane x2 = 0
/// (the crack inside), in local components at local x: the field of the circle's nearest point,
/// in its frame (a radial, n = x2, a x n).
void circleField(double ac, const TipElastic &e, const P3 &x, double s[3][3], double g[3][3]) {
  const double rin = std::hypot(x[0], x[2]), c = x[0] / rin, sn = x[2] / rin;
  const double E[3][3] = {{c, 0, sn}, {0, 1, 0}, {-sn, 0, c}}; // a, n, a x n
  double sf[3][3], gf[3][3];
  mixedField(kK, e, rin - ac, x[1], sf, gf);
  fromFrame(E, sf, s);
  fromFrame(E, gf, g);
}

/// The nv-gon of radius ac about the local origin in the plane x2 = 0, every edge a front.
CrackSurface circleCrack(const Placement &pl, double ac, int nv) {
  std::vector<P3> local;
  for (int k = 0; k < nv; ++k)
    local.push_back({ac * std::cos(2 * kPi * k / nv), 0, ac * std::sin(2 * kPi * k / nv)});
  return placedCrack(pl, local, true);
}

/// The relative errors (G, K_I, K_II, K_III) at front point f of the circle crack c (radius ac)
/// carrying circleField on a lattice along the local axes around f, and the relative difference
/// of G from the G of the measured K's.
std::array<double, 5> circleErrors(const Material &mat, const Placement &pl, const CrackSurface &c,
                                   double ac, const FrontPoint &f, double R, double L,
                                   AuxFrame aux) {
  const TipElastic e = gimp::cracks::frontElastic(mat);
  P3 P{}, lo, hi;
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < 3; ++i)
      P[a] += pl.B[a][i] * (f.x[i] - pl.c[i]);
  for (int a = 0; a < 3; ++a) {
    const double w = a == 1 ? R + 2 * kH : R + L + 2 * kH;
    lo[a] = std::round(P[a] / kH) * kH - w;
    hi[a] = std::round(P[a] / kH) * kH + w;
  }
  const Particles p(pl, lo, hi, kH, [&](const P3 &x, double s[3][3], double g[3][3]) {
    circleField(ac, e, x, s, g);
  });
  double sums[4] = {0, 0, 0, 0};
  gimp::cracks::addFrontIntegrals(mat, p.view, c, f, R, L, sums, aux);
  const gimp::cracks::FrontMeasure m = gimp::cracks::finishFront(mat, c, f, R, L, sums);
  const double Ep = mat.E / (1 - mat.nu * mat.nu);
  const double G = (kK[0] * kK[0] + kK[1] * kK[1]) / Ep + kK[2] * kK[2] / (2 * mat.mu);
  const double GK = (m.KI * m.KI + m.KII * m.KII) / Ep + m.KIII * m.KIII / (2 * mat.mu);
  return {m.G / G - 1, m.KI / kK[0] - 1, m.KII / kK[1] - 1, m.KIII / kK[2] - 1, m.G / GK - 1};
}

TEST(FrontIntegrals, CircularFrontRecoversTheKs) {
  const Material mat = material();
  const double R = 5 * kH, L = 5 * kH, ac = 40 * kH;
  const Placement pl = placement(true);
  const CrackSurface c = circleCrack(pl, ac, 64);
  const std::vector<FrontPoint> fp = gimp::cracks::frontPoints(c, 10 * kH);
  ASSERT_EQ(fp.size(), 64u);
  // A_q: the advance runs along each edge's own ahead direction, so the area it sweeps is the
  // integral of q_s alone, 16 L / 15 away from the chain's ends.
  const double Aq = 16.0 * L / 15.0;
  EXPECT_NEAR(gimp::cracks::frontArea(c, fp[0], L), Aq, 1e-8 * Aq);
  // The local field of a curved front is not an elastic solution (its stress has a divergence of
  // order K / (a sqrt(r))), so its J depends on the domain, linearly in R / a (below): at R / a =
  // 1 / 8 the measures are off by -2.9 to -3.1 % (G), +0.3 to +0.4 % (K_I), -5.0 to -5.5 % (K_II)
  // and -2.6 to -3.5 % (K_III) in either frame (the nearest point's with its curvature terms,
  // which assume an elastic field), alike at every point of the circle. With the arc length taken
  // from the nearest edge alone, which jumps behind each vertex (placeOf), they spread from point
  // to point: K_II -4 to -6.2 %, K_III -0.7 to -5.2 %. The bounds say where they are; the penny
  // cracks in the solver (elastic fields: tests/check_penny3d.py, check_penny_inclined3d.py) are
  // the checks of accuracy.
  const double bound[2][4] = {{0.035, 0.006, 0.06, 0.04}, {0.035, 0.006, 0.06, 0.04}};
  for (size_t q : {0u, 13u, 40u})
    for (int f = 0; f < 2; ++f) {
      const AuxFrame aux = f == 0 ? AuxFrame::Nearest : AuxFrame::Point;
      const auto err = circleErrors(mat, pl, c, ac, fp[q], R, L, aux);
      std::printf("circle a = 40 h, R = L = 5 h, point %2zu, aux frame %-7s: G %+.2f %%, KI %+.2f "
                  "%%, KII %+.2f %%, KIII %+.2f %%; G / G(K) - 1 %+.3f %%\n",
                  q, f == 0 ? "nearest" : "P", 100 * err[0], 100 * err[1], 100 * err[2],
                  100 * err[3], 100 * err[4]);
      for (int m = 0; m < 4; ++m)
        EXPECT_LT(std::fabs(err[static_cast<size_t>(m)]), bound[f][m])
            << "point " << q << " frame " << f << " measure " << m;
    }
}

TEST(FrontIntegrals, CircularFrontConvergesAsTheDomainShrinks) {
  // The error of that field is linear in R / a: on a circle of 80 h with the nearest point's
  // frame, the measure extrapolated to R = 0 from R = 10 h and 20 h, 2 E(10 h) - E(20 h), is
  // within 1 % (measured +0.40, +0.63, -0.51, -0.21 %; with the arc length of the nearest edge
  // alone +0.24, +0.59, -0.98, -0.78 %).
  const Material mat = material();
  const double ac = 80 * kH, L = 10 * kH;
  const Placement pl = placement(true);
  const CrackSurface c = circleCrack(pl, ac, 128);
  const FrontPoint f = gimp::cracks::frontPoints(c, 10 * kH)[0];
  const auto e10 = circleErrors(mat, pl, c, ac, f, 10 * kH, L, AuxFrame::Nearest);
  const auto e20 = circleErrors(mat, pl, c, ac, f, 20 * kH, L, AuxFrame::Nearest);
  for (int m = 0; m < 4; ++m) {
    const size_t i = static_cast<size_t>(m);
    std::printf("circle a = 80 h, measure %d: R = 10 h %+.2f %%, 20 h %+.2f %%, extrapolated to 0 "
                "%+.2f %%\n",
                m, 100 * e10[i], 100 * e20[i], 100 * (2 * e10[i] - e20[i]));
    EXPECT_LT(std::fabs(2 * e10[i] - e20[i]), 1e-2) << "measure " << m;
  }
}

TEST(FrontIntegrals, UniformStressHasNoK) {
  const Material mat = material();
  const double R = 5 * kH, L = 5 * kH, Z = 20 * kH, s0 = 1e6;
  const Placement pl = placement(true);
  const CrackSurface c =
      placedCrack(pl, {{-30 * kH, 0, -Z}, {0, 0, -Z}, {0, 0, Z}, {-30 * kH, 0, Z}}, false);
  const FrontPoint f = gimp::cracks::frontPoints(c, 2 * Z)[0];
  // s11, s33, s13 in the front's frame: the faces (normal x2) stay free.
  const double S[3][3] = {{s0, 0, 0.4 * s0}, {0, 0, 0}, {0.4 * s0, 0, -0.6 * s0}};
  const double tr = S[0][0] + S[2][2];
  double eps[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      eps[i][j] = ((1 + mat.nu) * S[i][j] - (i == j ? mat.nu * tr : 0.0)) / mat.E;
  const Particles p(pl, {-R - kH, -R - kH, -L - kH}, {R + kH, R + kH, L + kH}, kH,
                    [&](const P3 &, double s[3][3], double g[3][3]) {
                      for (int i = 0; i < 3; ++i)
                        for (int j = 0; j < 3; ++j) {
                          s[i][j] = S[i][j];
                          g[i][j] = eps[i][j];
                        }
                    });
  double sums[4] = {0, 0, 0, 0};
  gimp::cracks::addFrontIntegrals(mat, p.view, c, f, R, L, sums);
  const gimp::cracks::FrontMeasure m = gimp::cracks::finishFront(mat, c, f, R, L, sums);
  // The scale: the K of a stress s0 over the domain, s0 sqrt(pi R), and its G, s0^2 pi R / E.
  const double K = s0 * std::sqrt(kPi * R), G = K * K / mat.E;
  std::printf("uniform stress: G / (s0^2 pi R / E) %.2e, K / (s0 sqrt(pi R)) %.2e %.2e %.2e\n",
              m.G / G, m.KI / K, m.KII / K, m.KIII / K);
  EXPECT_LT(std::fabs(m.G), 1e-6 * G);
  EXPECT_LT(std::fabs(m.KI), 5e-3 * K);
  EXPECT_LT(std::fabs(m.KII), 5e-3 * K);
  EXPECT_LT(std::fabs(m.KIII), 5e-3 * K);
}

TEST(FrontIntegrals, PlaceIsContinuousBehindAVertex) {
  // The domain integral's divergence theorem needs q a continuous, and so the arc length s and
  // the ahead direction a of placeOf: behind a polygonal front, where a point's feet on two edges
  // are both interior, the nearest edge's arc length alone jumps by twice their distance from
  // the vertex on the plane that bisects the edges (front_chain.cpp). Walk along the front
  // through several vertices at depths behind it and heights above its plane, and ask that s and
  // a move by at most twice the step (a scaled by the front's radius), and that s keeps going
  // one way.
  const double ac = 40 * kH;
  const Placement pl = placement(true);
  const CrackSurface c = circleCrack(pl, ac, 64);
  const std::vector<FrontPoint> fp = gimp::cracks::frontPoints(c, 10 * kH);
  const chain::Chain ch = chain::chainOf(c, fp[0]);
  // The local axes of circleCrack in global coordinates: x = B^T x_local + c.
  auto toGlobal = [&](const P3 &xl) {
    P3 x{};
    for (int i = 0; i < 3; ++i) {
      x[i] = pl.c[i];
      for (int a = 0; a < 3; ++a)
        x[i] += pl.B[a][i] * xl[a];
    }
    return x;
  };
  double worstS = 0, worstA = 0;
  long turns = 0; // steps where s moves against the walk's first step
  const int n = 4000;
  const double phi0 = 2 * kPi * 3.3 / 64, phi1 = 2 * kPi * 7.7 / 64; // through four vertices
  for (const double depth : {0.5, 2.0, 4.5})
    for (const double height : {0.0, 1.5}) {
      const double r = ac - depth * kH;
      double sPrev = 0, sign = 0;
      P3 aPrev{}, xPrev{};
      for (int k = 0; k <= n; ++k) {
        const double phi = phi0 + (phi1 - phi0) * k / n;
        const P3 x = toGlobal({r * std::cos(phi), height * kH, r * std::sin(phi)});
        const chain::Place at = chain::placeOf(c, ch, x);
        if (k > 0) {
          const double step = chain::norm(chain::sub(x, xPrev));
          // |grad s| <= |t_k + t_n| <= 2 in a wedge; a turns by at most the ahead directions'
          // difference over an edge, 2 pi / 64 over about 2 pi ac / 64, per unit of s.
          worstS = std::max(worstS, std::fabs(at.s - sPrev) / (2.0 * step));
          worstA = std::max(worstA, chain::norm(chain::sub(at.a, aPrev)) * ac / (2.0 * step));
          if (k == 1) sign = at.s > sPrev ? 1 : -1;
          turns += sign * (at.s - sPrev) <= 0;
        }
        sPrev = at.s;
        aPrev = at.a;
        xPrev = x;
      }
    }
  std::printf("place behind the front: |ds| / (2 |dx|) at most %.3f, |da| ac / (2 |dx|) at most "
              "%.3f, s turning back %ld times\n",
              worstS, worstA, turns);
  EXPECT_LE(worstS, 1.0 + 1e-9);
  EXPECT_LE(worstA, 1.0 + 1e-9);
  EXPECT_EQ(turns, 0);
}

TEST(FrontIntegrals, MeasureFrontsIsTheSumOfItsPoints) {
  const Material mat = material();
  const TipElastic e = gimp::cracks::frontElastic(mat);
  const double R = 5 * kH, Z = 20 * kH;
  const Placement pl = placement(true);
  const CrackSurface c = placedCrack(
      pl, {{-30 * kH, 0, -Z}, {0, 0, -Z}, {0, 0, 0}, {0, 0, Z}, {-30 * kH, 0, Z}}, false);
  const Particles p(
      pl, {-R - kH, -R - kH, -Z}, {R + kH, R + kH, Z}, kH,
      [&](const P3 &x, double s[3][3], double g[3][3]) { mixedField(kK, e, x[0], x[1], s, g); });
  // Each point's own tube (Scene::jDomain): the asked radius, one clipped to 3 h, one where no
  // tube fits (radius 0: NaN measures, R = L = 0).
  const std::vector<FrontPoint> fp = gimp::cracks::frontPoints(c, 10 * kH);
  std::vector<gimp::JDomain> tubes(2 * fp.size(), {R, false});
  ASSERT_GE(tubes.size(), 4u);
  tubes[1] = {3 * kH, true};
  tubes[tubes.size() - 2] = {0.0, false};
  std::vector<gimp::cracks::FrontMeasure> out;
  ASSERT_EQ(gimp::cracks::measureFronts(PETSC_COMM_WORLD, {c, c}, mat, p.view, 10 * kH, tubes, R,
                                        {}, out),
            PETSC_SUCCESS);
  ASSERT_EQ(out.size(), 2 * fp.size());
  for (size_t q = 0; q < out.size(); ++q) {
    const FrontPoint &f = fp[q % fp.size()];
    const double Rq = tubes[q].radius;
    EXPECT_EQ(out[q].crack, static_cast<int>(q / fp.size()));
    EXPECT_EQ(out[q].edge, f.edge);
    EXPECT_EQ(out[q].asked, R);
    EXPECT_EQ(out[q].clipped, tubes[q].clipped);
    EXPECT_EQ(out[q].R, Rq);
    if (Rq == 0) {
      EXPECT_TRUE(std::isnan(out[q].G) && std::isnan(out[q].KI) && std::isnan(out[q].KII) &&
                  std::isnan(out[q].KIII));
      EXPECT_EQ(out[q].L, 0.0);
      continue;
    }
    double sums[4] = {0, 0, 0, 0};
    gimp::cracks::addFrontIntegrals(mat, p.view, c, f, Rq, Rq, sums);
    const gimp::cracks::FrontMeasure m = gimp::cracks::finishFront(mat, c, f, Rq, Rq, sums);
    // measureFronts takes an open chain's points together (addChainIntegrals): bit for bit.
    EXPECT_EQ(out[q].G, m.G);
    EXPECT_EQ(out[q].KI, m.KI);
    EXPECT_EQ(out[q].KII, m.KII);
    EXPECT_EQ(out[q].KIII, m.KIII);
    EXPECT_EQ(out[q].L, Rq);
  }
}

TEST(FrontIntegrals, MirrorImageCompletesTheTubeAtASymmetryPlane) {
  const Material mat = material();
  const TipElastic e = gimp::cracks::frontElastic(mat);
  const double R = 5 * kH, L = 5 * kH, Z = 20 * kH;
  const double K[3] = {1e6, 0.5e6, 0}; // modes I and II: a field the mirror z -> -z keeps
  const Placement pl = placement(false);
  const auto field = [&](const P3 &x, double s[3][3], double g[3][3]) {
    mixedField(K, e, x[0], x[1], s, g);
  };
  // The half body z >= 0 with its front from z = 0 (on the plane) to Z, and the whole body.
  const CrackSurface half =
      placedCrack(pl, {{-30 * kH, 0, 0}, {0, 0, 0}, {0, 0, Z}, {-30 * kH, 0, Z}}, false);
  const CrackSurface whole =
      placedCrack(pl, {{-30 * kH, 0, -Z}, {0, 0, -Z}, {0, 0, Z}, {-30 * kH, 0, Z}}, false);
  const double top = 2 * kH + L + 2 * kH;
  const Particles ph(pl, {-R - kH, -R - kH, 0}, {R + kH, R + kH, top}, kH, field);
  const Particles pw(pl, {-R - kH, -R - kH, -top}, {R + kH, R + kH, top}, kH, field);
  const auto at = [&](const CrackSurface &c) { // the front point at z = 2 h
    for (const FrontPoint &f : gimp::cracks::frontPoints(c, 4 * kH))
      if (std::fabs(f.x[2] - 2 * kH) < 1e-9) return f;
    ADD_FAILURE() << "no front point at z = 2 h";
    return FrontPoint{};
  };
  const FrontPoint fh = at(half), fw = at(whole);
  const std::vector<gimp::cracks::MirrorPlane> planes = {{2, 0.0}};
  double sh[4] = {0, 0, 0, 0}, sw[4] = {0, 0, 0, 0};
  gimp::cracks::addFrontIntegrals(mat, ph.view, half, fh, R, L, sh, AuxFrame::Nearest, planes);
  gimp::cracks::addFrontIntegrals(mat, pw.view, whole, fw, R, L, sw, AuxFrame::Nearest, {});
  const auto mh = gimp::cracks::finishFront(mat, half, fh, R, L, sh, planes);
  const auto mw = gimp::cracks::finishFront(mat, whole, fw, R, L, sw, {});
  EXPECT_EQ(mh.images, 1);
  EXPECT_EQ(mw.images, 0);
  EXPECT_NEAR(gimp::cracks::frontArea(half, fh, L, R, planes), 16 * L / 15, 1e-12 * L);
  const double Ks = std::hypot(K[0], K[1]);
  EXPECT_NEAR(mh.G, mw.G, 1e-11 * mw.G);
  EXPECT_NEAR(mh.KI, mw.KI, 1e-11 * Ks);
  EXPECT_NEAR(mh.KII, mw.KII, 1e-11 * Ks);
  EXPECT_NEAR(mh.KIII, mw.KIII, 1e-11 * Ks);
  EXPECT_LT(std::fabs(mh.KI / K[0] - 1), 1e-2);
  // Without the image the tube ends on the plane, where the mode II field's sigma_33 (plane
  // strain) meets the mode III auxiliary field's du_3/dx_1: a false K_III.
  double so[4] = {0, 0, 0, 0};
  gimp::cracks::addFrontIntegrals(mat, ph.view, half, fh, R, L, so);
  const auto mo = gimp::cracks::finishFront(mat, half, fh, R, L, so);
  std::printf("half tube at a symmetry plane: K_III / |K| %.1e with the image, %.1e without\n",
              mh.KIII / Ks, mo.KIII / Ks);
  EXPECT_GT(std::fabs(mo.KIII), 1e-2 * Ks);
  // A plane along the crack's normal (y = 0 here) holds no chain end: no image.
  EXPECT_EQ(gimp::cracks::finishFront(mat, half, fh, R, L, sh, {{1, 0.0}}).images, 0);
}

} // namespace
