// The moments of a particle cube cut by a sphere or a cylinder (geometry/cut_cell3d): exact
// cases, additivity over sub-boxes, an independent quadrature on random cases, and the
// equivalent box.
#include "gimp/geometry/cut_cell3d.hpp"

#include "gimp/geometry/cut_cell.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

using gimp::cut::boxBallMoments;
using gimp::cut::boxCylinderMoments;
using gimp::cut::Raw3;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// n-point Gauss-Legendre nodes and weights on [-1, 1] (Newton on the Legendre polynomial).
void gaussLegendre(int n, std::vector<double> &x, std::vector<double> &w) {
  x.resize(n);
  w.resize(n);
  for (int i = 0; i < n; ++i) {
    double t = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 1;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = t;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * t * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (t * p1 - p0) / (t * t - 1);
      const double dt = p1 / dp;
      t -= dt;
      if (std::fabs(dt) < 1e-16) break;
    }
    x[i] = t;
    w[i] = 2 / ((1 - t * t) * dp * dp);
  }
}

/// int f over [a, b] split at the cuts, each piece mapped by y = mid - half cos(theta), which
/// makes the square-root ends of a chord analytic, and integrated by 24-point Gauss rules on
/// 8 parts of [0, pi]: an independent route to near round-off.
template <class F> void integrate(double a, double b, std::vector<double> cuts, F f) {
  static std::vector<double> gx, gw;
  if (gx.empty()) gaussLegendre(24, gx, gw);
  cuts.push_back(a);
  cuts.push_back(b);
  std::sort(cuts.begin(), cuts.end());
  for (size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double lo = std::max(a, cuts[i]), hi = std::min(b, cuts[i + 1]);
    if (hi <= lo) continue;
    const double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
    for (int part = 0; part < 8; ++part)
      for (size_t q = 0; q < gx.size(); ++q) {
        const double th = kPi * (part + 0.5 + 0.5 * gx[q]) / 8, wt = kPi / 16 * gw[q];
        f(mid - half * std::cos(th), wt * half * std::sin(th));
      }
  }
}

/// The moments {A, Sy, Sz, Syy, Szz} of the rectangle [lo, hi] (y, z: indices 1, 2) cut by the
/// disk of centre (oy, oz) and radius rho: chords along z integrated over y.
std::array<double, 5> diskByChords(const double lo[3], const double hi[3], double oy, double oz,
                                   double rho) {
  std::array<double, 5> m{};
  std::vector<double> cuts;
  for (double zf : {lo[2], hi[2]}) // where the chord's end crosses a face z = zf
    if (std::fabs(zf - oz) < rho) {
      const double t = std::sqrt(rho * rho - (zf - oz) * (zf - oz));
      cuts.push_back(oy - t);
      cuts.push_back(oy + t);
    }
  integrate(std::max(lo[1], oy - rho), std::min(hi[1], oy + rho), cuts, [&](double y, double w) {
    const double s = std::sqrt(std::max(0.0, rho * rho - (y - oy) * (y - oy)));
    const double c0 = std::max(lo[2], oz - s), c1 = std::min(hi[2], oz + s);
    if (c1 <= c0) return;
    m[0] += w * (c1 - c0);
    m[1] += w * y * (c1 - c0);
    m[2] += w * 0.5 * (c1 * c1 - c0 * c0);
    m[3] += w * y * y * (c1 - c0);
    m[4] += w * (c1 * c1 * c1 - c0 * c0 * c0) / 3;
  });
  return m;
}

/// Raw moments of box cap ball: the disk slices along x (diskByChords) integrated over x,
/// split where a slice's disk reaches a side or a corner of the rectangle.
Raw3 ballByChords(const double lo[3], const double hi[3], const double o[3], double r) {
  Raw3 m{};
  std::vector<double> cuts;
  for (double dy : {lo[1] - o[1], hi[1] - o[1], 0.0})
    for (double dz : {lo[2] - o[2], hi[2] - o[2], 0.0}) {
      const double d2 = dy * dy + dz * dz;
      if (d2 == 0 || d2 >= r * r) continue;
      cuts.push_back(o[0] - std::sqrt(r * r - d2));
      cuts.push_back(o[0] + std::sqrt(r * r - d2));
    }
  integrate(std::max(lo[0], o[0] - r), std::min(hi[0], o[0] + r), cuts, [&](double x, double w) {
    const double rho = std::sqrt(std::max(0.0, r * r - (x - o[0]) * (x - o[0])));
    const auto s = diskByChords(lo, hi, o[1], o[2], rho);
    const double add[7] = {s[0], x * s[0], s[1], s[2], x * x * s[0], s[3], s[4]};
    for (int i = 0; i < 7; ++i)
      m[i] += w * add[i];
  });
  return m;
}

/// A cylinder along x (radius r through (o[1], o[2]), from zlo to zhi): its cross-section by
/// chords, times the length.
Raw3 cylinderByChords(const double lo[3], const double hi[3], const double o[3], double r,
                      double zlo, double zhi) {
  const double a = std::max(lo[0], zlo), b = std::min(hi[0], zhi);
  if (b <= a) return Raw3{};
  const auto s = diskByChords(lo, hi, o[1], o[2], r);
  const double L = b - a, X1 = 0.5 * (b * b - a * a), X2 = (b * b * b - a * a * a) / 3;
  return {s[0] * L, s[0] * X1, s[1] * L, s[2] * L, s[0] * X2, s[3] * L, s[4] * L};
}

/// The moments agree to rel of the box's own moments (about the origin, which the cases put
/// near the box).
void expectNear(const Raw3 &a, const Raw3 &b, const double lo[3], const double hi[3], double rel,
                const std::string &what) {
  double s = 0, V = 1;
  for (int k = 0; k < 3; ++k) {
    s = std::max({s, std::fabs(lo[k]), std::fabs(hi[k])});
    V *= hi[k] - lo[k];
  }
  const double scale[7] = {V, V * s, V * s, V * s, V * s * s, V * s * s, V * s * s};
  for (int i = 0; i < 7; ++i)
    EXPECT_NEAR(a[i], b[i], rel * scale[i]) << what << " moment " << i;
}

TEST(CutCell3D, BallInsideTheCubeIsExact) {
  // A ball smaller than the cube: 4/3 pi r^3, centroid o, int (x - o)^2 = 4 pi r^5 / 15.
  const double lo[3] = {-1, -1, -1}, hi[3] = {1, 1, 1}, o[3] = {0.1, -0.2, 0.3}, r = 0.55;
  const Raw3 m = boxBallMoments(lo, hi, o, r);
  const double V = 4 * kPi * r * r * r / 3, I = 4 * kPi * std::pow(r, 5) / 15;
  EXPECT_NEAR(m[0], V, 1e-14);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(m[1 + a], V * o[a], 1e-14);
    EXPECT_NEAR(m[4 + a], I + V * o[a] * o[a], 1e-14);
  }
}

TEST(CutCell3D, CubeInsideAndOutside) {
  const double lo[3] = {0.1, 0.2, -0.1}, hi[3] = {0.3, 0.4, 0.1}, o[3] = {0, 0, 0};
  const Raw3 in = boxBallMoments(lo, hi, o, 2.0);
  const Raw3 box = gimp::cut::boxBoxMoments(lo, hi, lo, hi);
  expectNear(in, box, lo, hi, 1e-14, "inside");
  const Raw3 out = boxBallMoments(lo, hi, o, 0.2);
  for (double v : out)
    EXPECT_EQ(v, 0.0);
  const Raw3 cyl = boxCylinderMoments(lo, hi, 2, o, 2.0, -1, 1);
  expectNear(cyl, box, lo, hi, 1e-14, "cylinder inside");
}

TEST(CutCell3D, SubBoxesAddUpToTheBall) {
  // A 7 x 7 x 7 lattice of boxes over the ball's box: the sums are the ball's moments to
  // round-off (every kind of cut: a face, an edge, a corner region, the poles).
  const double o[3] = {0.013, -0.021, 0.034}, r = 1.0, n = 7;
  Raw3 sum{};
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const int idx[3] = {i, j, k};
        double lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
          lo[a] = -1.1 + 2.2 * idx[a] / n;
          hi[a] = -1.1 + 2.2 * (idx[a] + 1) / n;
        }
        const Raw3 m = boxBallMoments(lo, hi, o, r);
        for (int q = 0; q < 7; ++q)
          sum[q] += m[q];
      }
  const double V = 4 * kPi / 3, I = 4 * kPi / 15;
  EXPECT_NEAR(sum[0], V, 1e-13 * V);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(sum[1 + a], V * o[a], 1e-13 * V);
    EXPECT_NEAR(sum[4 + a], I + V * o[a] * o[a], 1e-13 * V);
  }
}

TEST(CutCell3D, RandomCubesAgainstChords) {
  // Unit cubes about the origin against balls and cylinders placed to cut them anywhere: by a
  // face, an edge, a corner region, or smaller than the cube.
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), ur(0.2, 1.5);
  const double lo[3] = {-0.5, -0.5, -0.5}, hi[3] = {0.5, 0.5, 0.5};
  for (int t = 0; t < 12; ++t) {
    const double o[3] = {u(gen), u(gen), u(gen)}, r = ur(gen);
    expectNear(boxBallMoments(lo, hi, o, r), ballByChords(lo, hi, o, r), lo, hi, 1e-13,
               "ball " + std::to_string(t));
    const double zlo = -0.7 + 0.5 * u(gen), zhi = 0.7 + 0.5 * u(gen);
    expectNear(boxCylinderMoments(lo, hi, 0, o, r, zlo, zhi),
               cylinderByChords(lo, hi, o, r, zlo, zhi), lo, hi, 1e-13,
               "cylinder " + std::to_string(t));
  }
}

TEST(CutCell3D, EquivalentBoxOfABoxIsTheBox) {
  const double lo[3] = {0.1, 0.2, 0.3}, hi[3] = {0.4, 0.3, 0.9}, xc[3] = {0.25, 0.25, 0.6};
  Raw3 m = gimp::cut::boxBoxMoments(lo, hi, lo, hi);
  // About xc: shift the raw moments.
  Raw3 c{m[0]};
  for (int a = 0; a < 3; ++a) {
    c[1 + a] = m[1 + a] - m[0] * xc[a];
    c[4 + a] = m[4 + a] - 2 * xc[a] * m[1 + a] + m[0] * xc[a] * xc[a];
  }
  const gimp::cut::Moments3 mo = gimp::cut::fromRaw3(c, xc, m[0]);
  double l[3];
  gimp::cut::equivalentBox(mo, l);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(mo.c[a], xc[a], 1e-14);
    EXPECT_NEAR(l[a], 0.5 * (hi[a] - lo[a]), 1e-14);
  }
}

TEST(CutCell3D, ExtrudedCutKeepsItsSideAndThe2DRectangle) {
  // A cube cut by a cylinder along z: the box keeps the cube's side along z, and its in-plane
  // half-sizes are the equivalent rectangle of the disk's cut of the square.
  const double lo[3] = {-0.5, -0.5, -0.5}, hi[3] = {0.5, 0.5, 0.5}, o[3] = {0.7, 0.6, 0.0};
  const double side[3] = {1, 1, 1}, xc[3] = {0, 0, 0}, r = 0.8;
  const Raw3 m3 = boxCylinderMoments(lo, hi, 2, o, r, -1, 1);
  const gimp::cut::Moments3 m = gimp::cut::fromRaw3(m3, xc, 1.0);
  double l[3];
  gimp::cut::equivalentBox(m, l, side);
  const auto d = gimp::cut::rectDiskMoments(-0.5, -0.5, 0.5, 0.5, 0.7, 0.6, r);
  const gimp::cut::Moments m2 = gimp::cut::fromRaw(d, 0, 0, 1.0);
  double l2[2];
  gimp::cut::equivalentRectangle(m2, l2);
  EXPECT_NEAR(l[0], l2[0], 1e-14);
  EXPECT_NEAR(l[1], l2[1], 1e-14);
  EXPECT_NEAR(l[2], 0.5, 1e-14);
  EXPECT_NEAR(8 * l[0] * l[1] * l[2], m.V, 1e-14);
  // Without the sides every axis takes the scaling (the volume still the region's).
  gimp::cut::equivalentBox(m, l);
  EXPECT_NEAR(8 * l[0] * l[1] * l[2], m.V, 1e-14);
}

/// The volume of the boxes of an n^3 lattice over [-1.1, 1.1]^3 in the body and in no hole.
double latticeVolume(const gimp::cut::Round *body, const std::vector<gimp::cut::Round> &holes) {
  const int n = 7;
  double V = 0;
  for (int i = 0; i < n * n * n; ++i) {
    const int idx[3] = {i % n, (i / n) % n, i / (n * n)};
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = -1.1 + 2.2 * idx[a] / n;
      hi[a] = -1.1 + 2.2 * (idx[a] + 1) / n;
    }
    Raw3 m{};
    EXPECT_TRUE(gimp::cut::boxRoundsMoments(lo, hi, body, holes, m));
    V += m[0];
  }
  return V;
}

TEST(CutCell3D, CrossingSurfacesCountTheirCommonPartOnce) {
  // A ball of radius R with a cylinder of radius a through its centre along z (body: the ball
  // minus the cylinder, 4 pi / 3 (R^2 - a^2)^1.5), and a box with both as holes (the box minus
  // their union; their common part 4 pi / 3 (R^3 - (R^2 - a^2)^1.5)).
  gimp::cut::Round ball, rod;
  ball.c[0] = 0.013;
  ball.c[1] = -0.021;
  ball.r = 1.0;
  rod.ball = false;
  rod.axis = 2;
  rod.c[0] = 0.013;
  rod.c[1] = -0.021;
  rod.r = 0.43;
  const double R = 1.0, a = 0.43, ring = std::pow(R * R - a * a, 1.5);
  const double inBall = 4 * kPi / 3 * ring;
  EXPECT_NEAR(latticeVolume(&ball, {rod}), inBall, 1e-13);
  const double box = 2.2 * 2.2 * 2.2;
  const double holes = 4 * kPi / 3 + kPi * a * a * 2.2 - 4 * kPi / 3 * (R * R * R - ring);
  EXPECT_NEAR(latticeVolume(nullptr, {ball, rod}), box - holes, 1e-12);
  // Two cylinders across each other (along x and y): slices along z, both bands.
  gimp::cut::Round rx = rod, ry = rod;
  rx.axis = 0;
  ry.axis = 1;
  rx.c[2] = ry.c[2] = 0.02;
  const double r = a, common = 16.0 / 3.0 * r * r * r; // the Steinmetz solid
  EXPECT_NEAR(latticeVolume(nullptr, {rx, ry}), box - 2 * kPi * r * r * 2.2 + common, 1e-12);
}

} // namespace
