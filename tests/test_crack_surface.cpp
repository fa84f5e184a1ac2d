// The 3D crack polygon's geometry: crossing() against an independent segment-plane test, the
// perturbed-crack rules at the plane and the edges, distance, the front points and their frames,
// and the faults the scene refuses.
#include "gimp/geometry/crack_surface.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace gimp;
using P3 = std::array<double, 3>;

namespace {

/// A square [0, 1] x [0, 1] in the plane z = 0.25, normal +z.
CrackSurface square() {
  const double up[3] = {0, 0, 1};
  return cracks::makeSurface({{0, 0, 0.25}, {1, 0, 0.25}, {1, 1, 0.25}, {0, 1, 0.25}}, up);
}

} // namespace

TEST(CrackSurface, FrameAndOrientation) {
  // Given clockwise about +z with a +z hint: reversed to counter-clockwise.
  const double up[3] = {0, 0, 1};
  const CrackSurface c =
      cracks::makeSurface({{0, 0, 0.25}, {0, 1, 0.25}, {1, 1, 0.25}, {1, 0, 0.25}}, up);
  EXPECT_NEAR(c.normal[2], 1.0, 1e-15);
  const CrackSurface d = square();
  EXPECT_NEAR(d.normal[2], 1.0, 1e-15);
  EXPECT_NEAR(d.span, 2.0, 1e-15);
}

TEST(CrackSurface, CrossingAgainstPlaneTest) {
  const CrackSurface c = square();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  int crossed = 0;
  for (int k = 0; k < 20000; ++k) {
    const double a[3] = {u(rng), u(rng), u(rng) - 0.25}, b[3] = {u(rng), u(rng), u(rng) - 0.25};
    // Independent: the segment's point at z = 0.25 inside the open unit square.
    int expect = 0;
    if ((a[2] - 0.25) * (b[2] - 0.25) < 0) {
      const double t = (0.25 - a[2]) / (b[2] - a[2]);
      const double x = a[0] + t * (b[0] - a[0]), y = a[1] + t * (b[1] - a[1]);
      if (x > 0 && x < 1 && y > 0 && y < 1) expect = a[2] > 0.25 ? 1 : -1;
    }
    const int got = cracks::crossing(c, a, b);
    ASSERT_EQ(got, expect) << k;
    ASSERT_EQ(cracks::crossing(c, b, a), -expect);
    crossed += got != 0;
  }
  EXPECT_GT(crossed, 1000);
}

TEST(CrackSurface, PointsOnThePlaneAreOnItsNormalSide) {
  const CrackSurface c = square();
  const double on[3] = {0.5, 0.5, 0.25}, above[3] = {0.5, 0.5, 0.5}, below[3] = {0.5, 0.5, 0.0};
  EXPECT_EQ(cracks::crossing(c, on, above), 0);
  EXPECT_EQ(cracks::crossing(c, on, below), 1);
  EXPECT_EQ(cracks::crossing(c, below, on), -1);
  EXPECT_EQ(cracks::sideOf(c, 0, on), 1);
  EXPECT_EQ(cracks::sideOf(c, 0, below), -1);
  // Through a front edge, or beside the polygon: no crossing; through a mouth edge: crossing.
  const double e0[3] = {1.0, 0.5, 0.5}, e1[3] = {1.0, 0.5, 0.0};
  EXPECT_EQ(cracks::crossing(c, e0, e1), 1); // every edge a mouth
  CrackSurface f = c;
  f.front = {0, 1, 0, 0}; // the edge x = 1 a front
  EXPECT_EQ(cracks::crossing(f, e0, e1), 0);
  // A node on the plane at a corner where the front meets a mouth: outside.
  const double k0[3] = {1.0, 1.0, 0.5}, k1[3] = {1.0, 1.0, 0.0};
  EXPECT_EQ(cracks::crossing(f, k0, k1), 0);
  const double o0[3] = {1.2, 0.5, 0.5}, o1[3] = {1.2, 0.5, 0.0};
  EXPECT_EQ(cracks::crossing(c, o0, o1), 0);
}

TEST(CrackSurface, Distance) {
  const CrackSurface c = square();
  const double in[3] = {0.5, 0.5, 0.75}, out[3] = {1.3, 0.5, 0.65};
  EXPECT_NEAR(cracks::distance(c, in), 0.5, 1e-15);
  EXPECT_NEAR(cracks::distance(c, out), 0.5, 1e-15);
  const double box[6] = {1.1, 0.4, 0.2, 1.2, 0.5, 0.3};
  EXPECT_TRUE(cracks::nearCrack(c, box, 0.1));
  const double far[6] = {2.1, 0.4, 0.2, 2.2, 0.5, 0.3};
  EXPECT_FALSE(cracks::nearCrack(c, far, 0.1));
}

TEST(CrackSurface, NearestPointAndBehindFront) {
  // An L-shaped polygon in z = 0.25: its nearest point against a brute-force
  // search over a fine sampling of the region, at random points around it.
  const double up[3] = {0, 0, 1};
  CrackSurface c = cracks::makeSurface(
      {{0, 0, 0.25}, {1, 0, 0.25}, {1, 0.5, 0.25}, {0.5, 0.5, 0.25}, {0.5, 1, 0.25}, {0, 1, 0.25}},
      up);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  const int n = 200;
  for (int k = 0; k < 200; ++k) {
    const double x[3] = {u(rng), u(rng), u(rng)};
    const P3 p = cracks::nearestPoint(c, x);
    EXPECT_EQ(p[2], 0.25);
    const double d = std::hypot(std::hypot(x[0] - p[0], x[1] - p[1]), x[2] - p[2]);
    EXPECT_NEAR(d, cracks::distance(c, x), 1e-14);
    double best = 1e300;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) {
        const double a = static_cast<double>(i) / n, b = static_cast<double>(j) / n;
        if (a > 0.5 && b > 0.5) continue; // (the L's notch)
        best = std::min(best, std::hypot(std::hypot(x[0] - a, x[1] - b), x[2] - 0.25));
      }
    EXPECT_LE(d, best + 1e-15);
    EXPECT_GE(d, best - 1.0 / n);
  }
  // Behind the front: inside, and farther than tol from the front edges (here the edges x = 1
  // and y = 1 and the notch's two), not from the mouths (x = 0, y = 0).
  c.front = {0, 1, 1, 1, 1, 0};
  const double tol = 1e-9;
  const auto behind = [&](double x, double y) {
    const double q[3] = {x, y, 0.7}; // (off the plane: projected)
    return cracks::behindFront(c, q, tol);
  };
  EXPECT_TRUE(behind(0.2, 0.2));
  EXPECT_TRUE(behind(1e-12, 0.3)); // beside a mouth
  EXPECT_TRUE(behind(1 - 2 * tol, 0.2));
  EXPECT_FALSE(behind(1 - 0.5 * tol, 0.2)); // on a front edge, within tol
  EXPECT_FALSE(behind(1.0, 0.2));
  EXPECT_FALSE(behind(0.5, 0.7)); // on the notch's front
  EXPECT_FALSE(behind(0.7, 0.7)); // in the notch
  EXPECT_FALSE(behind(1.2, 0.2));
}

TEST(CrackSurface, FrontPointsAndFrames) {
  CrackSurface c = square();
  c.front = {1, 0, 0, 0}; // the edge along y = 0
  const auto f = cracks::frontPoints(c, 0.3);
  ASSERT_EQ(f.size(), 4u);
  EXPECT_NEAR(f[0].x[0], 0.125, 1e-15);
  EXPECT_NEAR(f[3].x[0], 0.875, 1e-15);
  // Ahead of the edge y = 0 is -y, away from the crack.
  EXPECT_NEAR(f[0].a[1], -1.0, 1e-15);
  EXPECT_NEAR(f[0].n[2], 1.0, 1e-15);
  EXPECT_NEAR(f[0].t[0], 1.0, 1e-15);
}

TEST(CrackSurface, Faults) {
  const double tol = 1e-9;
  EXPECT_EQ(cracks::findFault({{0, 0, 0}, {1, 0, 0}}, tol).kind, cracks::SurfaceFault::Degenerate);
  EXPECT_EQ(cracks::findFault({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, tol).kind,
            cracks::SurfaceFault::Degenerate);
  EXPECT_EQ(cracks::findFault({{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {0, 1, 0}}, tol).kind,
            cracks::SurfaceFault::ZeroLength);
  EXPECT_EQ(cracks::findFault({{0, 0, 0}, {1, 0, 0}, {1, 1, 0.1}, {0, 1, 0}}, tol).kind,
            cracks::SurfaceFault::NotPlanar);
  // A bow tie crosses itself.
  EXPECT_EQ(cracks::findFault({{0, 0, 0}, {3, 1, 0}, {3, 0, 0}, {0, 2, 0}}, tol).kind,
            cracks::SurfaceFault::Intersects);
  EXPECT_EQ(cracks::findFault({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, tol).kind,
            cracks::SurfaceFault::None);
}

TEST(CrackSurface, SurfacesMeet) {
  const CrackSurface a = square();
  const double x[3] = {1, 0, 0};
  // A vertical square through a's middle crosses it; one beside it does not.
  const CrackSurface b =
      cracks::makeSurface({{0.5, -1, 0}, {0.5, 2, 0}, {0.5, 2, 1}, {0.5, -1, 1}}, x);
  const CrackSurface c =
      cracks::makeSurface({{1.5, -1, 0}, {1.5, 2, 0}, {1.5, 2, 1}, {1.5, -1, 1}}, x);
  double at[3];
  EXPECT_TRUE(cracks::surfacesMeet(a, b, at));
  EXPECT_NEAR(at[2], 0.25, 1e-12);
  EXPECT_FALSE(cracks::surfacesMeet(a, c, at));
}
