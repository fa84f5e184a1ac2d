// Body shapes (geometry/shape): the moments of a square's part inside a rectangle, ellipse or
// polygon add up over a tiling to the shape's exact moments; points in and out; simple-polygon
// validation; holes inside bodies and overlapping shapes.
#include "gimp/geometry/shape.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using gimp::Shape;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// The raw moments {A, Sx, Sy, Sxx, Syy} about the origin of the shape, summed over the n x n
/// squares tiling [x0, x1] x [y0, y1], each taken about its own centre and moved to the origin.
std::array<double, 5> tiled(const Shape &s, double x0, double y0, double x1, double y1, int n) {
  std::array<double, 5> t{};
  const double dx = (x1 - x0) / n, dy = (y1 - y0) / n;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double a = x0 + i * dx, b = y0 + j * dy, ox = a + 0.5 * dx, oy = b + 0.5 * dy;
      const auto m = s.momentsIn(a, b, a + dx, b + dy, ox, oy);
      // int (x' + o)^k dA from the moments about o.
      t[0] += m[0];
      t[1] += m[1] + ox * m[0];
      t[2] += m[2] + oy * m[0];
      t[3] += m[3] + 2 * ox * m[1] + ox * ox * m[0];
      t[4] += m[4] + 2 * oy * m[2] + oy * oy * m[0];
    }
  return t;
}

void expectMoments(const std::array<double, 5> &got, const std::array<double, 5> &want,
                   double scale, double tol) {
  for (int k = 0; k < 5; ++k)
    EXPECT_NEAR(got[k], want[k], tol * scale) << "moment " << k;
}

TEST(Shape, EllipseMomentsAddUpOverATiling) {
  // Off-centre, a != b, on tilings that do not line up with it.
  const double cx = 0.31, cy = -0.17, a = 0.23, b = 0.11;
  const Shape e = Shape::ellipse(cx, cy, a, b);
  const double A = kPi * a * b;
  const std::array<double, 5> exact = {A, A * cx, A * cy, A * (cx * cx + a * a / 4),
                                       A * (cy * cy + b * b / 4)};
  for (int n : {7, 16, 33}) {
    SCOPED_TRACE(n);
    expectMoments(tiled(e, -0.05, -0.41, 0.71, 0.13, n), exact, A, 1e-13);
  }
  // The circle (a = b) takes the disk route.
  const Shape c = Shape::ellipse(cx, cy, a, a);
  const double Ac = kPi * a * a;
  expectMoments(tiled(c, -0.05, -0.41, 0.71, 0.13, 19),
                {Ac, Ac * cx, Ac * cy, Ac * (cx * cx + a * a / 4), Ac * (cy * cy + a * a / 4)}, Ac,
                1e-13);
}

/// Exact moments of a polygon by its triangles from the first vertex (a different route from
/// the code's edge sums after clipping).
std::array<double, 5> triangleFan(const std::vector<double> &xy) {
  std::array<double, 5> m{};
  const size_t n = xy.size() / 2;
  for (size_t i = 1; i + 1 < n; ++i) {
    const double x[3] = {xy[0], xy[2 * i], xy[2 * i + 2]},
                 y[3] = {xy[1], xy[2 * i + 1], xy[2 * i + 3]};
    const double A = 0.5 * ((x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]));
    m[0] += A;
    m[1] += A * (x[0] + x[1] + x[2]) / 3;
    m[2] += A * (y[0] + y[1] + y[2]) / 3;
    // int x^2 over a triangle: A/6 (x0^2 + x1^2 + x2^2 + x0 x1 + x1 x2 + x2 x0).
    m[3] +=
        A / 6 * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + x[0] * x[1] + x[1] * x[2] + x[2] * x[0]);
    m[4] +=
        A / 6 * (y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[0] * y[1] + y[1] * y[2] + y[2] * y[0]);
  }
  return m;
}

TEST(Shape, PolygonMomentsAddUpOverATiling) {
  // A non-convex polygon (a notched bar whose notch is a V), given clockwise: stored
  // counter-clockwise. Its fan from vertex 0 stays inside it, so the fan is its moments.
  const std::vector<double> cw = {0.0,  0.0,  0.0, 0.3, 0.45, 0.3, 0.5,
                                  0.18, 0.55, 0.3, 1.0, 0.3,  1.0, 0.0};
  const Shape p = Shape::polygon(cw);
  ASSERT_EQ(gimp::polygonProblem(cw), "");
  const auto exact = triangleFan(p.xy);
  EXPECT_GT(exact[0], 0);
  for (int n : {5, 12, 41}) {
    SCOPED_TRACE(n);
    expectMoments(tiled(p, -0.13, -0.07, 1.09, 0.37, n), exact, exact[0], 1e-13);
  }
}

TEST(Shape, RectangleMomentsAreTheOverlap) {
  const Shape r = Shape::rectangle(0.1, 0.2, 0.4, 0.9);
  const auto m = r.momentsIn(0.3, 0.0, 0.6, 0.5, 0.45, 0.25); // overlap [0.3, 0.4] x [0.2, 0.5]
  EXPECT_NEAR(m[0], 0.1 * 0.3, 1e-15);
  EXPECT_NEAR(m[1] / m[0], 0.35 - 0.45, 1e-14);
  EXPECT_NEAR(m[2] / m[0], 0.35 - 0.25, 1e-14);
  EXPECT_EQ(r.momentsIn(0.5, 0.0, 0.6, 0.1, 0.55, 0.05)[0], 0.0);
}

TEST(Shape, PointsInAndOut) {
  const Shape e = Shape::ellipse(0, 0, 2, 1);
  EXPECT_TRUE(e.contains(1.9, 0.0));
  EXPECT_TRUE(e.contains(2.0, 0.0)); // on the boundary
  EXPECT_FALSE(e.strictlyInside(2.0, 0.0));
  EXPECT_FALSE(e.contains(1.5, 0.7));                             // 0.5625 + 0.49 > 1
  const Shape p = Shape::polygon({0, 0, 2, 0, 2, 2, 1, 1, 0, 2}); // an arrow notch from the top
  EXPECT_TRUE(p.contains(0.5, 0.5));
  EXPECT_FALSE(p.contains(1.0, 1.5)); // in the notch
  EXPECT_TRUE(p.contains(1.0, 1.0));  // the notch's tip, on the boundary
  EXPECT_FALSE(p.strictlyInside(1.0, 1.0));
}

TEST(Shape, PolygonProblems) {
  EXPECT_EQ(gimp::polygonProblem({0, 0, 1, 0, 0, 1}), "");
  EXPECT_NE(gimp::polygonProblem({0, 0, 1, 0}).find("at least 3"), std::string::npos);
  EXPECT_NE(gimp::polygonProblem({0, 0, 1, 0, 0}).find("pairs"), std::string::npos);
  EXPECT_NE(gimp::polygonProblem({0, 0, 1, 1, 1, 0, 0, 1}).find("crosses itself"),
            std::string::npos);                            // a bow tie
  EXPECT_NE(gimp::polygonProblem({0, 0, 1, 0, 2, 0}), ""); // collinear: folds back
  EXPECT_NE(gimp::polygonProblem({0, 0, 1, 0, 1, 0.5, 1, 1e-300}), "");
  EXPECT_NE(gimp::polygonProblem({0, 0, 1, 0, 1, 0, 0, 1}).find("repeated"), std::string::npos);
  EXPECT_NE(gimp::polygonProblem({0, 0, NAN, 0, 0, 1}).find("finite"), std::string::npos);
  // A spike that folds back along its own edge.
  EXPECT_NE(gimp::polygonProblem({0, 0, 2, 0, 1, 0, 1, 1}), "");
}

TEST(Shape, InsideAndOverlap) {
  const Shape bar = Shape::polygon({0, 0, 4, 0, 4, 1, 2.2, 1, 2, 0.5, 1.8, 1, 0, 1});
  EXPECT_TRUE(Shape::ellipse(1, 0.5, 0.3, 0.3).insideOf(bar));
  EXPECT_FALSE(Shape::ellipse(2, 0.6, 0.3, 0.3).insideOf(bar)); // the notch reaches into it
  EXPECT_FALSE(Shape::ellipse(3.9, 0.5, 0.3, 0.3).insideOf(bar));
  // Touching disks do not overlap; overlapping ones do; one inside another does.
  const Shape a = Shape::ellipse(0.2, 0.2, 0.2, 0.2);
  EXPECT_FALSE(a.overlaps(Shape::ellipse(0.6, 0.2, 0.2, 0.2)));
  EXPECT_TRUE(a.overlaps(Shape::ellipse(0.55, 0.2, 0.2, 0.2)));
  EXPECT_TRUE(a.overlaps(Shape::ellipse(0.2, 0.2, 0.05, 0.05)));
  EXPECT_TRUE(a.overlaps(a));
  EXPECT_FALSE(Shape::rectangle(0, 0, 1, 1).overlaps(Shape::rectangle(1, 0, 2, 1)));
}

} // namespace
