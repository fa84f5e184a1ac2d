// Unit tests of crack growth's pieces (include/gimp/cracks/growth.hpp): the maximum hoop stress
// kink (mtsKink), the 3D twist angle, and the 3D polygon after its front advanced (advanceFront)
// and the region its growth may reach (growthReach).
//
//   1. Pure mode I: no kink. Pure mode II: -arccos(1/3) = -70.53 degrees for K_II > 0 (the
//      root of K_I sin theta + K_II (3 cos theta - 1) = 0 with K_I = 0).
//   2. Antisymmetry in K_II: theta(K_I, -K_II) = -theta(K_I, K_II); scale invariance.
//   3. At every ratio the angle is a root of the hoop stress's stationarity condition,
//      K_I sin theta + K_II (3 cos theta - 1) = 0, and the hoop stress there is a maximum.
//   4. Small K_II: no cancellation: theta = -2 K_II / K_I to first order, with full relative
//      accuracy at K_II / K_I = 1e-12.
//   5. The twist: pure mode III 45 degrees, the closed form in between, antisymmetric in K_III.
//   6. A regular polygon (a disk's) advanced by s everywhere: the regular polygon whose edges lie
//      s farther out, to round-off; the same count of vertices.
//   7. A square advanced along one side only (two pieces per side): that side's middle vertex
//      moves by s along its ahead direction, the corners by the mean of their pieces' advances
//      along their bisectors (s / 2 along each axis), the rest stays.
//   8. A through crack whose front meets mouths at a body's surfaces: the front moves by s, the
//      mouths' far vertices come along, the straight mouth vertices left behind are dropped.
//   9. growthReach holds every point within 1.25 growth lengths of the front, and stops short of
//      points beyond that by more than its polygon's circumscription allows.
//  10. The increments being released (-gimp_crack_growth_release): those grown less than the
//      release time ago, at either end, each with its segment from the tip before it; none
//      without a release time.
#include "gimp/cracks/growth.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

namespace {

using P3 = std::array<double, 3>;

using gimp::cracks::mtsKink;

constexpr double kPi = 3.141592653589793;

double deg(double rad) {
  return rad * 180.0 / kPi;
}

/// The hoop stress at angle theta (times sqrt(2 pi r)), of the tip's K fields.
double hoop(double KI, double KII, double th) {
  const double c = std::cos(0.5 * th);
  return c * (KI * c * c - 1.5 * KII * std::sin(th));
}

TEST(MtsKink, PureModes) {
  EXPECT_EQ(mtsKink(1.0, 0.0), 0.0);
  EXPECT_EQ(mtsKink(3.7e5, 0.0), 0.0);
  EXPECT_NEAR(deg(mtsKink(0.0, 1.0)), -70.528779365509, 1e-9);
  EXPECT_NEAR(mtsKink(0.0, 2.5e6), -std::acos(1.0 / 3.0), 1e-14);
  EXPECT_NEAR(deg(mtsKink(0.0, -1.0)), 70.528779365509, 1e-9);
}

TEST(MtsKink, AntisymmetricAndScaleFree) {
  for (double r : {-3.0, -0.4, 0.01, 0.577, 1.0, 5.0, 100.0}) {
    const double a = mtsKink(1.0, r);
    EXPECT_EQ(mtsKink(1.0, -r), -a) << r;
    EXPECT_NEAR(mtsKink(2.0e5, 2.0e5 * r), a, 1e-15) << r;
    EXPECT_LT(a * r, 0.0) << "K_II > 0 kinks clockwise (negative), K_II < 0 counter-clockwise";
  }
}

TEST(MtsKink, StationaryMaximumOfTheHoopStress) {
  for (double KI : {1.0, 0.3, 0.0, -0.2}) // (a closed crack, K_I < 0, too)
    for (double KII : {-2.0, -0.5, -1e-3, 1e-3, 0.5, 1.0, 2.0}) {
      const double th = mtsKink(KI, KII);
      EXPECT_NEAR(KI * std::sin(th) + KII * (3.0 * std::cos(th) - 1.0), 0.0,
                  1e-13 * (std::fabs(KI) + std::fabs(KII)))
          << KI << " " << KII;
      const double d = 1e-4;
      EXPECT_GT(hoop(KI, KII, th), hoop(KI, KII, th + d)) << KI << " " << KII;
      EXPECT_GT(hoop(KI, KII, th), hoop(KI, KII, th - d)) << KI << " " << KII;
    }
}

TEST(MtsKink, InclinedCrackUnderTension) {
  // K_II / K_I = tan(beta) for a crack at beta to the plane normal to the load.
  EXPECT_NEAR(deg(mtsKink(std::cos(kPi / 6), std::sin(kPi / 6))), -43.2213451190, 1e-8);
  EXPECT_NEAR(deg(mtsKink(1.0, 1.0)), -53.1301023542, 1e-8);
  EXPECT_NEAR(deg(mtsKink(1.0, std::sqrt(3.0))), -60.0, 1e-9);
}

TEST(MtsKink, SmallModeIINoCancellation) {
  const double r = 1e-12;
  EXPECT_NEAR(mtsKink(1.0, r) / (-2.0 * r), 1.0, 1e-12);
}

TEST(Twist, ModeIIIAndClosedForm) {
  using gimp::cracks::twistAngle;
  EXPECT_EQ(twistAngle(1.0, 0.0, 0.3), 0.0);
  EXPECT_NEAR(deg(twistAngle(0.0, 1.0, 0.3)), 45.0, 1e-12);
  const double KI = 1.0, KIII = 0.1, nu = 0.3;
  EXPECT_NEAR(twistAngle(KI, KIII, nu), 0.5 * std::atan(2 * KIII / ((1 - 2 * nu) * KI)), 1e-15);
  EXPECT_EQ(twistAngle(KI, -KIII, nu), -twistAngle(KI, KIII, nu));
}

gimp::CrackSurface planar(const std::vector<P3> &pts, const std::vector<char> &front) {
  const double up[3] = {0, 0, 1};
  gimp::CrackSurface c = gimp::cracks::makeSurface(pts, up);
  c.front = front;
  return c;
}

TEST(AdvanceFront, RegularPolygonStaysRegular) {
  const int n = 40;
  const double r = 0.01, s = 1e-3;
  std::vector<P3> pts;
  for (int k = 0; k < n; ++k)
    pts.push_back({r * std::cos(2 * kPi * k / n), r * std::sin(2 * kPi * k / n), 0.5});
  const gimp::CrackSurface c = planar(pts, std::vector<char>(n, 1));
  const double spacing = 1.0; // one piece per edge
  const std::vector<double> adv(gimp::cracks::frontPoints(c, spacing).size(), s);
  const std::vector<P3> out = gimp::cracks::advanceFront(c, spacing, adv);
  ASSERT_EQ(out.size(), pts.size());
  const double R = r + s / std::cos(kPi / n); // the vertices of the polygon s farther out
  for (int k = 0; k < n; ++k) {
    EXPECT_NEAR(out[k][0], R * std::cos(2 * kPi * k / n), 1e-15);
    EXPECT_NEAR(out[k][1], R * std::sin(2 * kPi * k / n), 1e-15);
    EXPECT_EQ(out[k][2], 0.5);
  }
}

TEST(AdvanceFront, OneSideOfASquare) {
  // Counter-clockwise about +z: ahead of the side x = 1 is +x.
  const gimp::CrackSurface c = planar({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {1, 1, 1, 1});
  const double spacing = 0.5, s = 0.125;
  const std::vector<gimp::cracks::FrontPoint> fp = gimp::cracks::frontPoints(c, spacing);
  ASSERT_EQ(fp.size(), 8u);
  std::vector<double> adv(8, 0.0);
  adv[2] = adv[3] = s; // the pieces of edge 1 (x = 1)
  const std::vector<P3> out = gimp::cracks::advanceFront(c, spacing, adv);
  const std::vector<P3> want = {{0, 0, 0},
                                {0.5, 0, 0},
                                {1 + s / 2, -s / 2, 0},
                                {1 + s, 0.5, 0},
                                {1 + s / 2, 1 + s / 2, 0},
                                {0.5, 1, 0},
                                {0, 1, 0},
                                {0, 0.5, 0}};
  ASSERT_EQ(out.size(), want.size());
  for (size_t k = 0; k < want.size(); ++k)
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(out[k][a], want[k][a], 1e-15) << k << " " << a;
}

TEST(AdvanceFront, ThroughCrackCarriesItsMouths) {
  // The crack in z = 0, x < a, across a body 0 <= y <= T and past it by 1 on both sides: the
  // edge x = a is a front between y = 0 and T (where classifyCrackEdges cut it), a mouth beyond.
  const double a = 0.3, T = 0.2, s = 0.05;
  const gimp::CrackSurface c =
      planar({{-1, -1, 0}, {a, -1, 0}, {a, 0, 0}, {a, T, 0}, {a, T + 1, 0}, {-1, T + 1, 0}},
             {0, 0, 1, 0, 0, 0});
  const std::vector<P3> out = gimp::cracks::advanceFront(c, 1.0, {s});
  const std::vector<P3> want = {{-1, -1, 0},   {a + s, -1, 0},    {a + s, 0, 0},
                                {a + s, T, 0}, {a + s, T + 1, 0}, {-1, T + 1, 0}};
  ASSERT_EQ(out.size(), want.size());
  for (size_t k = 0; k < want.size(); ++k)
    for (int q = 0; q < 3; ++q)
      EXPECT_NEAR(out[k][q], want[k][q], 1e-15) << k << " " << q;
}

TEST(GrowthReach, HoldsTheFrontsNeighbourhood) {
  const gimp::CrackSurface c = planar({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {0, 1, 1, 0});
  const double L = 0.25;
  const gimp::CrackSurface r = gimp::cracks::growthReach(c, L);
  EXPECT_EQ(r.normal[2], 1.0);
  // Within 1.25 L of the front (the sides x = 1 and y = 1 and their corner), and the crack.
  for (const P3 &x : std::vector<P3>{{1 + 1.249 * L, 0.5, 0},
                                     {0.5, 1 + 1.249 * L, 0},
                                     {1 + 0.88 * L, 1 + 0.88 * L, 0},
                                     {1 + 0.88 * L, -0.88 * L, 0},
                                     {0.5, 0.5, 0},
                                     {0, 0, 0}})
    EXPECT_EQ(gimp::cracks::distance(r, x.data()), 0.0) << x[0] << " " << x[1];
  // Beyond the circumscribed 16-gons about the front's vertices.
  for (const P3 &x :
       std::vector<P3>{{1 + 1.28 * L, 0.5, 0}, {1 + 0.93 * L, 1 + 0.93 * L, 0}, {-0.2, -0.2, 0}})
    EXPECT_GT(gimp::cracks::distance(r, x.data()), 0.0) << x[0] << " " << x[1];
}

TEST(Release, IncrementsStillOpening) {
  gimp::Scene<2> sc;
  sc.growthRelease = 1e-3;
  gimp::Crack c;
  // Grown once at end 0 and twice at end 1 (the last increment kinked).
  c.points = {{-0.003, 0.012}, {-0.002, 0.012}, {0.050, 0.012}, {0.051, 0.012}, {0.052, 0.0125}};
  sc.cracks = {c};
  std::vector<gimp::cracks::GrowthRecord> grown(3);
  grown[0].t = 1.0e-3, grown[0].end = 1, grown[0].x[0] = 0.051, grown[0].x[1] = 0.012;
  grown[1].t = 1.8e-3, grown[1].end = 1, grown[1].x[0] = 0.052, grown[1].x[1] = 0.0125;
  grown[2].t = 1.9e-3, grown[2].end = 0, grown[2].x[0] = -0.003, grown[2].x[1] = 0.012;
  const auto r = gimp::cracks::releasing(sc, grown, 2.5e-3);
  ASSERT_EQ(r.size(), 2u); // (the first grew 1.5 ms ago: released)
  EXPECT_EQ(r[0].t0, 1.8e-3);
  EXPECT_EQ(r[0].from, (std::array<double, 2>{0.051, 0.012}));
  EXPECT_EQ(r[0].to, (std::array<double, 2>{0.052, 0.0125}));
  EXPECT_EQ(r[1].t0, 1.9e-3);
  EXPECT_EQ(r[1].from, (std::array<double, 2>{-0.002, 0.012}));
  EXPECT_EQ(r[1].to, (std::array<double, 2>{-0.003, 0.012}));
  EXPECT_EQ(gimp::cracks::releasing(sc, grown, 2.8e-3).size(), 1u); // (0.9 ms after the last)
  EXPECT_TRUE(gimp::cracks::releasing(sc, grown, 3.0e-3).empty());
  sc.growthRelease = 0;
  EXPECT_TRUE(gimp::cracks::releasing(sc, grown, 1.9e-3).empty());
}

TEST(Release, FrontAdvancesStillOpening) {
  // 3D: each advance of a front keeps its crack's polygon before it (FrontGrowth::opening).
  gimp::Scene<3> sc;
  sc.growthRelease = 1e-3;
  const auto square = [](double a) {
    return planar({{0, 0, 0}, {a, 0, 0}, {a, 1, 0}, {0, 1, 0}}, {0, 1, 0, 0});
  };
  sc.frontGrowth.resize(2);
  sc.frontGrowth[0].crack = 0;
  sc.frontGrowth[0].opening = {{1.0e-3, square(0.1)}, {1.8e-3, square(0.2)}};
  sc.frontGrowth[1].crack = 1;
  sc.frontGrowth[1].opening = {{1.9e-3, square(0.3)}};
  const auto r = gimp::cracks::releasing(sc, 2.5e-3);
  ASSERT_EQ(r.size(), 2u); // (the first grew 1.5 ms ago: released)
  EXPECT_EQ(r[0].crack, 0);
  EXPECT_EQ(r[0].t0, 1.8e-3);
  EXPECT_EQ(r[0].before.points, square(0.2).points);
  EXPECT_EQ(r[0].before.front, square(0.2).front);
  EXPECT_EQ(r[1].crack, 1);
  EXPECT_EQ(r[1].t0, 1.9e-3);
  EXPECT_EQ(r[1].before.points, square(0.3).points);
  EXPECT_EQ(gimp::cracks::releasing(sc, 2.8e-3).size(), 1u);
  EXPECT_TRUE(gimp::cracks::releasing(sc, 3.0e-3).empty());
  sc.growthRelease = 0;
  EXPECT_TRUE(gimp::cracks::releasing(sc, 1.9e-3).empty());
}

} // namespace
