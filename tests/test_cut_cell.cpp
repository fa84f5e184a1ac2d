// The moments of a particle square cut by circular holes (geometry/cut_cell): exact cases,
// additivity over sub-rectangles, an independent quadrature, and the equivalent rectangle.
#include "gimp/geometry/cut_cell.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using gimp::cut::Moments;
using gimp::cut::rectDiskMoments;
using gimp::cut::rectMinusDisks;

namespace {

/// int {1, x, y, x^2, y^2} over rectangle cap disk by composite Gauss rules in y of the exact
/// chord in x: an independent route (the code integrates over x in the angle), accurate to about
/// 1e-9 (the chord's square-root ends and its kinks are not split out).
std::array<double, 5> byChords(double x0, double y0, double x1, double y1, double ox, double oy,
                               double r) {
  const double g[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, w[3] = {5 / 9., 8 / 9., 5 / 9.};
  std::array<double, 5> m{};
  const double a = std::max(y0, oy - r), b = std::min(y1, oy + r);
  const int panels = 40000;
  for (int p = 0; p < panels && b > a; ++p) {
    const double lo = a + (b - a) * p / panels, hi = a + (b - a) * (p + 1) / panels;
    for (int q = 0; q < 3; ++q) {
      const double y = 0.5 * (lo + hi) + 0.5 * (hi - lo) * g[q], wt = 0.5 * (hi - lo) * w[q];
      const double half = std::sqrt(std::max(0.0, r * r - (y - oy) * (y - oy)));
      const double xa = std::max(x0, ox - half), xb = std::min(x1, ox + half);
      if (xb <= xa) continue;
      m[0] += wt * (xb - xa);
      m[1] += wt * 0.5 * (xb * xb - xa * xa);
      m[2] += wt * y * (xb - xa);
      m[3] += wt * (xb * xb * xb - xa * xa * xa) / 3.0;
      m[4] += wt * y * y * (xb - xa);
    }
  }
  return m;
}

} // namespace

TEST(CutCell, WholeDiskInsideTheRectangle) {
  const double ox = 0.3, oy = -0.2, r = 0.7, A = M_PI * r * r;
  const auto m = rectDiskMoments(-1, -1, 2, 1, ox, oy, r);
  EXPECT_NEAR(m[0], A, 1e-14);
  EXPECT_NEAR(m[1], A * ox, 1e-14);
  EXPECT_NEAR(m[2], A * oy, 1e-14);
  EXPECT_NEAR(m[3], A * (ox * ox + r * r / 4), 1e-14);
  EXPECT_NEAR(m[4], A * (oy * oy + r * r / 4), 1e-14);
}

TEST(CutCell, RectangleInsideTheDiskAndMissingIt) {
  const auto in = rectDiskMoments(0.1, 0.2, 0.3, 0.5, 0, 0, 2.0);
  EXPECT_NEAR(in[0], 0.2 * 0.3, 1e-15);
  EXPECT_NEAR(in[1], 0.2 * 0.3 * 0.2, 1e-15);
  const auto out = rectDiskMoments(3, 3, 4, 4, 0, 0, 2.0);
  for (double v : out)
    EXPECT_EQ(v, 0.0);
  // A rectangle inside a hole is removed entirely; one the hole misses is kept whole.
  EXPECT_EQ(rectMinusDisks(0.1, 0.2, 0.3, 0.5, {{0, 0, 2.0}}).A, 0.0);
  const Moments whole = rectMinusDisks(3, 3, 4, 5, {{0, 0, 2.0}});
  EXPECT_NEAR(whole.A, 2.0, 1e-15);
  EXPECT_NEAR(whole.cx, 3.5, 1e-15);
  EXPECT_NEAR(whole.Iyy, 2.0 * 4 / 12, 1e-15);
}

TEST(CutCell, HalfAndQuarterDisk) {
  const double r = 1.3;
  const auto half = rectDiskMoments(0, -2, 2, 2, 0, 0, r);
  EXPECT_NEAR(half[0], M_PI * r * r / 2, 1e-14);
  EXPECT_NEAR(half[1] / half[0], 4 * r / (3 * M_PI), 1e-14);
  EXPECT_NEAR(half[2], 0.0, 1e-14);
  const auto quarter = rectDiskMoments(0, 0, 2, 2, 0, 0, r);
  EXPECT_NEAR(quarter[0], M_PI * r * r / 4, 1e-14);
  EXPECT_NEAR(quarter[2] / quarter[0], 4 * r / (3 * M_PI), 1e-14);
}

TEST(CutCell, AdditiveOverSubRectanglesAndEqualToChordQuadrature) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int t = 0; t < 200; ++t) {
    const double ox = u(gen), oy = u(gen), r = 0.2 + std::fabs(u(gen));
    double x0 = u(gen), x1 = u(gen), y0 = u(gen), y1 = u(gen);
    if (x1 < x0) std::swap(x0, x1);
    if (y1 < y0) std::swap(y0, y1);
    const double xm = x0 + (x1 - x0) * std::fabs(u(gen)), ym = y0 + (y1 - y0) * std::fabs(u(gen));
    const auto all = rectDiskMoments(x0, y0, x1, y1, ox, oy, r);
    std::array<double, 5> sum{};
    for (const auto &q :
         {rectDiskMoments(x0, y0, xm, ym, ox, oy, r), rectDiskMoments(xm, y0, x1, ym, ox, oy, r),
          rectDiskMoments(x0, ym, xm, y1, ox, oy, r), rectDiskMoments(xm, ym, x1, y1, ox, oy, r)})
      for (int i = 0; i < 5; ++i)
        sum[i] += q[i];
    const auto ref = byChords(x0, y0, x1, y1, ox, oy, r);
    for (int i = 0; i < 5; ++i) {
      EXPECT_NEAR(sum[i], all[i], 1e-14) << "case " << t << " moment " << i;
      EXPECT_NEAR(ref[i], all[i], 1e-8) << "case " << t << " moment " << i;
    }
  }
}

TEST(CutCell, EquivalentRectangleKeepsTheAreaAndTheAspect) {
  // An uncut rectangle is its own equivalent.
  const Moments m = rectMinusDisks(0, 0, 0.4, 0.1, {});
  double l[2];
  gimp::cut::equivalentRectangle(m, l);
  EXPECT_NEAR(l[0], 0.2, 1e-15);
  EXPECT_NEAR(l[1], 0.05, 1e-15);
  // A square whose corner a large hole removes: area kept, centroid inside the square.
  const Moments c = rectMinusDisks(0.9, 0.9, 1.1, 1.1, {{0, 0, 1.35}});
  gimp::cut::equivalentRectangle(c, l);
  EXPECT_NEAR(4 * l[0] * l[1], c.A, 1e-15);
  EXPECT_GT(c.cx, 0.9);
  EXPECT_GT(c.cy, 0.9);
  EXPECT_NEAR(l[0], l[1], 1e-14); // symmetric about the diagonal
  EXPECT_LT(c.A, 0.04);
}
