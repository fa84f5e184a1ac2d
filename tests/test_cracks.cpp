// Unit tests of the crack geometry in include/gimp/geometry/crack.hpp.
//
//   1. crossing() against an independent brute-force reference on random straight and kinked
//      cracks: each segment pair solved as two lines (Cramer's rule, a + t (b - a) = p + s (q - p),
//      crossing when 0 < t, s < 1), parity and the side of a at the crossing nearest to a. Samples
//      within 1e-6 of a degenerate case (an end on a line, a line through a vertex) are left to
//      the convention tests. Here and in 3, crossing() asked of the segments near the pair's box
//      alone (segmentsNear) gives the same answer.
//   2. The conventions on hand-made cases: side signs, the open end at a tip, segments parallel
//      to and along the crack, a segment ending on the crack, a segment through a kink, a point
//      at a kink or at a tip; crossing(a, b) == -crossing(b, a) for one crossing.
//   3. Consistency on lattices full of degenerate cases (points on the crack, lines through its
//      vertices): around every triangle the crossings add up, mod 2, to the number of crack ends
//      inside it, which holds only if every convention is that of one perturbed crack.
//   4. distance, normalAt and nearCrack against dense sampling of the polyline; findFault.
// Random samples use a fixed-seed std::mt19937_64.
#include "gimp/geometry/crack.hpp"

#include "test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>

namespace {

using gimp::Crack;
using gimp::cracks::crossing;
using gimp::test::at;
using Point = std::array<double, 2>;

double cross(double ux, double uy, double vx, double vy) {
  return ux * vy - uy * vx;
}

/// The brute-force reference; sets `marginal` when the sample is within 1e-6 of a degenerate
/// case (relative to the lengths involved), and the number of crossings.
int reference(const Crack &c, const Point &a, const Point &b, bool &marginal, int &count) {
  int side = 0;
  count = 0;
  double nearest = 2;
  const double ux = b[0] - a[0], uy = b[1] - a[1];
  for (size_t k = 0; k + 1 < c.points.size(); ++k) {
    const Point &p = c.points[k], &q = c.points[k + 1];
    const double vx = q[0] - p[0], vy = q[1] - p[1];
    const double den = cross(ux, uy, vx, vy);
    const double scale = std::hypot(ux, uy) * std::hypot(vx, vy);
    if (std::fabs(den) < 1e-6 * scale) {
      // (nearly) parallel: crossing only if collinear, which sampling never hits exactly
      if (std::fabs(cross(vx, vy, a[0] - p[0], a[1] - p[1])) < 1e-6 * scale) marginal = true;
      continue;
    }
    const double t = cross(p[0] - a[0], p[1] - a[1], vx, vy) / den;
    const double s = cross(p[0] - a[0], p[1] - a[1], ux, uy) / den;
    for (double v : {t, 1 - t, s, 1 - s})
      if (std::fabs(v) < 1e-6) marginal = true;
    if (t > 0 && t < 1 && s > 0 && s < 1) {
      ++count;
      if (t < nearest) {
        nearest = t;
        side = cross(vx, vy, a[0] - p[0], a[1] - p[1]) > 0 ? 1 : -1;
      }
    }
  }
  return count % 2 ? side : 0;
}

Crack randomCrack(std::mt19937_64 &rng, int npoints) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (;;) {
    Crack c;
    for (int i = 0; i < npoints; ++i)
      c.points.push_back({u(rng), u(rng)});
    if (gimp::cracks::findFault(c, 1e-3).kind == gimp::cracks::PolylineFault::None) return c;
  }
}

/// crossing() asked of the segments near the box of a and b (segmentsNear), as the stencils ask
/// it: it must give crossing()'s answer.
int nearAnswer(const Crack &c, const Point &a, const Point &b) {
  const double box[4] = {std::min(a[0], b[0]), std::min(a[1], b[1]), std::max(a[0], b[0]),
                         std::max(a[1], b[1])};
  std::vector<int> segs;
  gimp::cracks::segmentsNear(c, box, segs);
  return crossing(c, segs, a[0], a[1], b[0], b[1]);
}

void compareWithReference(int npoints, int ncracks, int nsegments) {
  std::mt19937_64 rng(npoints);
  std::uniform_real_distribution<double> u(-0.3, 1.3);
  long compared = 0, counts[3] = {0, 0, 0};
  for (int k = 0; k < ncracks; ++k) {
    const Crack c = randomCrack(rng, npoints);
    for (int i = 0; i < nsegments; ++i) {
      const Point a{u(rng), u(rng)};
      // Short segments (stencil-like) and long ones (several crossings).
      const double len = i % 2 ? 0.05 : 1.0;
      const Point b{a[0] + len * (u(rng) - 0.5), a[1] + len * (u(rng) - 0.5)};
      bool marginal = false;
      int count = 0;
      const int want = reference(c, a, b, marginal, count);
      if (marginal) continue;
      ++compared;
      ++counts[want + 1];
      const int got = crossing(c, a[0], a[1], b[0], b[1]);
      ASSERT_EQ(got, want) << at(
          {{"crack", k}, {"ax", a[0]}, {"ay", a[1]}, {"bx", b[0]}, {"by", b[1]}});
      ASSERT_EQ(nearAnswer(c, a, b), got);
      if (count == 1) {
        ASSERT_EQ(crossing(c, b[0], b[1], a[0], a[1]), -want);
      }
    }
  }
  std::printf("  %d-point cracks: %ld samples compared: %ld from the right, %ld none, %ld from the "
              "left\n",
              npoints, compared, counts[0], counts[1], counts[2]);
  EXPECT_GT(counts[0], compared / 50);
  EXPECT_GT(counts[2], compared / 50);
}

TEST(Crossing, StraightCracksAgainstBruteForce) {
  compareWithReference(2, 200, 2000);
}

TEST(Crossing, KinkedCracksAgainstBruteForce) {
  compareWithReference(3, 200, 2000);
  compareWithReference(6, 200, 2000);
}

TEST(Crossing, SideSigns) {
  const Crack c{{{0, 0}, {1, 0}}, {true, true}};   // left: y > 0
  EXPECT_EQ(crossing(c, 0.5, 0.1, 0.5, -0.1), 1);  // from the left
  EXPECT_EQ(crossing(c, 0.5, -0.1, 0.5, 0.1), -1); // from the right
  const Crack r{{{1, 0}, {0, 0}}, {true, true}};   // reversed: left is y < 0
  EXPECT_EQ(crossing(r, 0.5, 0.1, 0.5, -0.1), -1);
  EXPECT_EQ(crossing(r, 0.5, -0.1, 0.5, 0.1), 1);
  EXPECT_EQ(crossing(c, 0.5, 0.1, 0.6, 0.2), 0); // same side
  EXPECT_EQ(crossing(c, 0.5, 0.1, 0.5, 0.1), 0); // a == b
}

TEST(Crossing, OpenEndAtTip) {
  const Crack c{{{0.2, 0.1}, {0.7, 0.35}}, {false, true}};
  // Segments across the crack's line at the tip (0.7, 0.35), offset along the crack by e.
  const double tx = 0.5 / std::hypot(0.5, 0.25), ty = 0.25 / std::hypot(0.5, 0.25);
  for (double e : {-1e-3, -1e-6, -1e-7, 0.0, 1e-7, 1e-6, 1e-3}) {
    const double x = 0.7 + e * tx, y = 0.35 + e * ty;
    const int want = e < 0 ? 1 : 0; // before the tip it crosses, through or beyond it not
    EXPECT_EQ(crossing(c, x + 0.01 * ty, y - 0.01 * tx, x - 0.01 * ty, y + 0.01 * tx), -want)
        << "e = " << e;
    EXPECT_EQ(crossing(c, x - 0.01 * ty, y + 0.01 * tx, x + 0.01 * ty, y - 0.01 * tx), want)
        << "e = " << e;
  }
  // The first point is an end too (a mouth here): nothing crosses through or beyond it.
  EXPECT_EQ(crossing(c, 0.2, 0.0, 0.2, 0.2), 0);
  EXPECT_EQ(crossing(c, 0.2 + 1e-7, 0.0, 0.2 + 1e-7, 0.2), -1);
  // A point at the tip or a mouth is on no side: nothing from it or to it crosses.
  for (double ang = 0; ang < 6.3; ang += 0.1) {
    EXPECT_EQ(crossing(c, 0.7, 0.35, 0.7 + 0.05 * std::cos(ang), 0.35 + 0.05 * std::sin(ang)), 0);
    EXPECT_EQ(crossing(c, 0.2 + 0.05 * std::cos(ang), 0.1 + 0.05 * std::sin(ang), 0.2, 0.1), 0);
  }
}

TEST(Crossing, ParallelAndAlongTheCrack) {
  const Crack c{{{0, 0}, {1, 0}, {2, 1}}, {false, false}};
  for (double y : {-0.1, -1e-12, 0.0, 1e-12, 0.1}) {
    EXPECT_EQ(crossing(c, -0.5, y, 0.7, y), 0) << y; // parallel, or along, past an end
    EXPECT_EQ(crossing(c, 0.2, y, 0.7, y), 0) << y;  // parallel, or along, inside
    // Onto the kink at (1, 0) and past it: from the crack (its left) into the right region.
    EXPECT_EQ(crossing(c, 0.9, y, 1.05, y), std::fabs(y) < 1e-9 ? 1 : 0) << y;
  }
  // Along the second segment's line, parallel on either side.
  EXPECT_EQ(crossing(c, 1.2, 0.2, 1.8, 0.8), 0);
  EXPECT_EQ(crossing(c, 1.2, 0.25, 1.8, 0.85), 0);
  EXPECT_EQ(crossing(c, 1.2, 0.15, 1.8, 0.75), 0);
}

TEST(Crossing, SegmentEndingOnTheCrack) {
  // Convention: a point on the crack is on its left. A node on the crack belongs to the left:
  // entries from the right cross it, entries from the left do not.
  const Crack c{{{0, 0.2}, {1, 0.2}}, {false, false}}; // left: y > 0.2
  const double node = 3 * 0.1 - 0.1;                   // 0.2 up to rounding, as a grid computes it
  for (double y : {0.2, node, 0.2 + 1e-13, 0.2 - 1e-13}) {
    EXPECT_EQ(crossing(c, 0.45, 0.15, 0.5, y), -1) << y; // from the right onto the crack
    EXPECT_EQ(crossing(c, 0.5, y, 0.45, 0.15), 1) << y;  // and back
    EXPECT_EQ(crossing(c, 0.45, 0.25, 0.5, y), 0) << y;  // from the left
    EXPECT_EQ(crossing(c, 0.5, y, 0.45, 0.25), 0) << y;
    EXPECT_EQ(crossing(c, 0.3, y, 0.5, y), 0) << y; // along the crack
  }
  EXPECT_EQ(crossing(c, 0.45, 0.2 - 1e-6, 0.5, 0.25), -1); // just below: a real crossing
}

TEST(Crossing, ThroughAKink) {
  const Crack v{{{-1, 1}, {0, 0}, {1, 1}}, {true, true}}; // left turn: left is y > |x|
  EXPECT_EQ(crossing(v, 0, -1, 0, 0.5), -1);              // through the vertex, right to left
  EXPECT_EQ(crossing(v, 0, 0.5, 0, -1), 1);
  EXPECT_EQ(crossing(v, -0.5, 0, 0.5, 0), 0);      // touches the kink from below
  EXPECT_EQ(crossing(v, -0.9, 0.5, 0.9, 0.5), 0);  // through both arms: parity
  EXPECT_EQ(crossing(v, -0.9, 0.5, 0.2, 0.5), -1); // one arm, from outside the V (right)
  // The mitre of a right turn: the segment along the bisector crosses once.
  const Crack w{{{-1, -1}, {0, 0}, {1, -1}}, {true, true}}; // right turn: left is y > -|x|
  EXPECT_EQ(crossing(w, 0, -0.5, 0, 0.5), -1);
  EXPECT_EQ(crossing(w, -0.5, 0, 0.5, 0), 0); // touches the kink from above
}

TEST(Crossing, PointAtAKink) {
  // A node at an interior vertex is on the crack's left there: particles in the right region
  // cross to it, particles in the left region do not. Both turn directions, all angles.
  for (double turn : {1.0, -1.0}) {
    const Crack c{{{-1, turn}, {0, 0}, {1, turn}}, {true, true}};
    for (int i = 0; i < 720; ++i) {
      const double ang = i * 3.14159265358979 / 360, x = std::cos(ang), y = std::sin(ang);
      if (std::fabs(std::fabs(x) - std::fabs(y)) < 1e-12) continue; // along an arm: tested below
      const bool left = turn > 0 ? y > std::fabs(x) : y > -std::fabs(x);
      EXPECT_EQ(crossing(c, x, y, 0, 0), left ? 0 : -1) << turn << " " << ang;
      EXPECT_EQ(crossing(c, 0, 0, x, y), left ? 0 : 1) << turn << " " << ang;
    }
    EXPECT_EQ(crossing(c, -0.5, 0.5 * turn, 0, 0), 0); // along an arm
  }
}

/// Points of a small lattice, scaled: orientation tests on it are exact (scale 1) or carry
/// rounding (scale 0.1, offset 0.3).
std::vector<Point> lattice(double scale, double offset) {
  std::vector<Point> pts;
  for (int i = -2; i <= 3; ++i)
    for (int j = -2; j <= 3; ++j)
      pts.push_back({offset + scale * i, offset + scale * j});
  return pts;
}

/// Whether p lies strictly inside the triangle abc (false on its boundary, which sets onEdge).
bool inTriangle(const Point &p, const Point &a, const Point &b, const Point &c, bool &onEdge) {
  const Point *v[3] = {&a, &b, &c};
  int pos = 0, neg = 0;
  for (int k = 0; k < 3; ++k) {
    const Point &s = *v[k], &e = *v[(k + 1) % 3];
    const double o = cross(e[0] - s[0], e[1] - s[1], p[0] - s[0], p[1] - s[1]);
    const double tol = 1e-9 * (std::hypot(e[0] - s[0], e[1] - s[1]) + 1) * 4;
    if (std::fabs(o) <= tol * std::hypot(e[0] - s[0], e[1] - s[1])) {
      const double lo0 = std::min(s[0], e[0]), hi0 = std::max(s[0], e[0]);
      const double lo1 = std::min(s[1], e[1]), hi1 = std::max(s[1], e[1]);
      if (p[0] >= lo0 - tol && p[0] <= hi0 + tol && p[1] >= lo1 - tol && p[1] <= hi1 + tol)
        onEdge = true;
      continue;
    }
    (o > 0 ? pos : neg) += 1;
  }
  return pos == 3 || neg == 3;
}

void loopParity(double scale, double offset) {
  const std::vector<Point> pts = lattice(scale, offset);
  auto P = [&](double i, double j) { return Point{offset + scale * i, offset + scale * j}; };
  const Crack cracks[] = {{{P(-1, 0), P(2, 0)}, {true, true}},
                          {{P(-1, 1), P(0, 0), P(1, 1), P(2, -1), P(3, 1)}, {true, true}},
                          {{P(-2, -2), P(0, 0), P(2, 0), P(2, 2)}, {true, true}}};
  long loops = 0;
  for (const Crack &c : cracks)
    for (size_t i = 0; i < pts.size(); ++i)
      for (size_t j = 0; j < pts.size(); ++j)
        for (size_t k = 0; k < pts.size(); k += 3) {
          const Point &a = pts[i], &b = pts[j], &d = pts[k];
          bool onEdge = false;
          int ends = inTriangle(c.points.front(), a, b, d, onEdge) ? 1 : 0;
          ends += inTriangle(c.points.back(), a, b, d, onEdge) ? 1 : 0;
          if (onEdge) continue;
          const int sum = std::abs(crossing(c, a[0], a[1], b[0], b[1])) +
                          std::abs(crossing(c, b[0], b[1], d[0], d[1])) +
                          std::abs(crossing(c, d[0], d[1], a[0], a[1]));
          ++loops;
          ASSERT_EQ((sum + ends) % 2, 0)
              << at({{"ax", a[0]},
                     {"ay", a[1]},
                     {"bx", b[0]},
                     {"by", b[1]},
                     {"cx", d[0]},
                     {"cy", d[1]},
                     {"crack points", static_cast<double>(c.points.size())}});
          ASSERT_EQ(crossing(c, a[0], a[1], b[0], b[1]) != 0,
                    crossing(c, b[0], b[1], a[0], a[1]) != 0);
          ASSERT_EQ(nearAnswer(c, a, b), crossing(c, a[0], a[1], b[0], b[1]));
        }
  std::printf("  scale %g: %ld loops consistent\n", scale, loops);
}

TEST(Crossing, LoopsOnLatticesAreConsistent) {
  loopParity(1.0, 0.0);
  loopParity(0.1, 0.3);
}

TEST(Crossing, Speed) {
  std::mt19937_64 rng(7);
  const Crack c = randomCrack(rng, 10);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> x(4000);
  for (double &v : x)
    v = u(rng);
  long n = 0, hits = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int rep = 0; rep < 500; ++rep)
    for (size_t i = 0; i + 3 < x.size(); i += 2, ++n)
      hits += crossing(c, x[i], x[i + 1], x[i] + 0.05 * (x[i + 2] - 0.5),
                       x[i + 1] + 0.05 * (x[i + 3] - 0.5)) != 0;
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("  %ld calls on a 9-segment crack (%ld crossing): %.1f ns per call\n", n, hits,
              1e9 * s / n);
  EXPECT_GT(hits, 0);
}

/// Dense samples of the polyline, spacing at most `step`.
std::vector<Point> samples(const Crack &c, double step) {
  std::vector<Point> s;
  for (size_t k = 0; k + 1 < c.points.size(); ++k) {
    const Point &p = c.points[k], &q = c.points[k + 1];
    const int n = static_cast<int>(std::ceil(std::hypot(q[0] - p[0], q[1] - p[1]) / step));
    for (int i = 0; i <= n; ++i)
      s.push_back({p[0] + (q[0] - p[0]) * i / n, p[1] + (q[1] - p[1]) * i / n});
  }
  return s;
}

TEST(Geometry, DistanceAndNormal) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  const double step = 1e-4;
  for (int k = 0; k < 20; ++k) {
    const Crack c = randomCrack(rng, 2 + k % 5);
    const std::vector<Point> s = samples(c, step);
    for (int i = 0; i < 200; ++i) {
      const double x = u(rng), y = u(rng);
      double best = 1e300;
      for (const Point &p : s)
        best = std::min(best, std::hypot(x - p[0], y - p[1]));
      const double d = gimp::cracks::distance(c, x, y);
      EXPECT_LE(d, best + 1e-12);
      EXPECT_GE(d, best - step);
      double n[2];
      const int seg = gimp::cracks::normalAt(c, x, y, n);
      const Point &p = c.points[seg], &q = c.points[seg + 1];
      EXPECT_NEAR(std::hypot(n[0], n[1]), 1.0, 1e-14);
      EXPECT_NEAR(n[0] * (q[0] - p[0]) + n[1] * (q[1] - p[1]), 0.0, 1e-14);
      EXPECT_GT(cross(q[0] - p[0], q[1] - p[1], n[0], n[1]), 0); // left of the direction
      double segDist = 1e300;                                    // seg is the nearest
      for (size_t m = 0; m + 1 < c.points.size(); ++m)
        segDist = std::min(
            segDist, gimp::cracks::segmentDistance({x, y}, {x, y}, c.points[m], c.points[m + 1]));
      EXPECT_NEAR(gimp::cracks::segmentDistance({x, y}, {x, y}, p, q), segDist, 1e-15);
    }
  }
  const Crack c{{{0, 0}, {1, 0}}, {false, false}};
  double n[2];
  EXPECT_EQ(gimp::cracks::normalAt(c, 0.5, -3, n), 0);
  EXPECT_DOUBLE_EQ(n[0], 0.0);
  EXPECT_DOUBLE_EQ(n[1], 1.0);
  EXPECT_DOUBLE_EQ(gimp::cracks::distance(c, 2, 0), 1.0);
}

// A grid node computed on the crack line with rounding error (a refined level's coordinates)
// must be on the side crossing() gives it, or the contact normal of its two fields points the
// wrong way and the faces of an open crack are pressed together.
TEST(Geometry, SideOfANodeOnTheLineAgreesWithCrossing) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 2000; ++k) {
    const Point p{u(rng), u(rng)}, q{u(rng), u(rng)};
    const Crack c{{p, q}, {false, false}};
    const double s = 0.1 + 0.8 * u(rng);
    double x = p[0] + s * (q[0] - p[0]), y = p[1] + s * (q[1] - p[1]);
    for (int ulp = -3; ulp <= 3; ++ulp) { // the node a few roundings off the line
      const double yn = ulp < 0 ? std::nextafter(y, -1.0) : ulp > 0 ? std::nextafter(y, 2.0) : y;
      double n[2];
      gimp::cracks::normalAt(c, x, yn, n);
      const double h = 0.01; // particles well off the line on either side
      const int side = gimp::cracks::sideOf(c, 0, x, yn);
      for (const double sgn : {1.0, -1.0}) {
        const double px = x + sgn * h * n[0], py = yn + sgn * h * n[1];
        // The particle's field at the node is the node's own (no crossing) exactly when they
        // are on the same side.
        EXPECT_EQ(gimp::cracks::crossing(c, px, py, x, yn) == 0, (sgn > 0) == (side > 0));
      }
      y = yn;
    }
  }
  // The node y = 0.08 of a level at 0.079999999999999988 is on the line, hence on the left.
  const Crack c{{{0.07, 0.08}, {0.09, 0.08}}, {true, true}};
  EXPECT_EQ(gimp::cracks::sideOf(c, 0, 0.08, std::nextafter(0.08, 0.0)), 1);
  EXPECT_EQ(gimp::cracks::sideOf(c, 0, 0.08, 0.08 - 1e-6), -1);
}

TEST(Geometry, NearCrack) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(-0.5, 1.5), w(0.0, 0.2);
  const double step = 1e-4;
  long near = 0, far = 0;
  for (int k = 0; k < 20; ++k) {
    const Crack c = randomCrack(rng, 2 + k % 5);
    const std::vector<Point> s = samples(c, step);
    for (int i = 0; i < 500; ++i) {
      const double x = u(rng), y = u(rng), box[4] = {x, y, x + w(rng), y + w(rng)};
      const double reach = w(rng);
      double best = 1e300; // distance from the box to the samples
      for (const Point &p : s)
        best = std::min(best, std::hypot(std::max({box[0] - p[0], 0.0, p[0] - box[2]}),
                                         std::max({box[1] - p[1], 0.0, p[1] - box[3]})));
      if (std::fabs(best - reach) < 2 * step) continue;
      const bool want = best < reach;
      (want ? near : far) += 1;
      EXPECT_EQ(gimp::cracks::nearCrack(c, box, reach), want)
          << at({{"x0", box[0]}, {"y0", box[1]}, {"x1", box[2]}, {"y1", box[3]}, {"reach", reach}});
    }
  }
  std::printf("  %ld boxes near a crack, %ld not\n", near, far);
  EXPECT_GT(near, 100);
  EXPECT_GT(far, 100);
  const Crack inside{{{0.4, 0.4}, {0.6, 0.6}}, {true, true}};
  const double box[4] = {0, 0, 1, 1};
  EXPECT_TRUE(gimp::cracks::nearCrack(inside, box, 0.0)); // wholly inside the box
}

TEST(Geometry, PolylineFaults) {
  using gimp::cracks::findFault;
  using F = gimp::cracks::PolylineFault;
  auto kind = [](std::vector<Point> p) { return findFault(Crack{p, {false, false}}, 1e-9).kind; };
  EXPECT_EQ(kind({{0, 0}, {1, 0}}), F::None);
  EXPECT_EQ(kind({{0, 0}, {1, 0}, {1, 1}, {0, 1}}), F::None); // a U is fine
  EXPECT_EQ(kind({{0, 0}, {1, 0}, {1, 0}}), F::ZeroLength);
  EXPECT_EQ(kind({{0, 0}, {1, 0}, {0.5, 0}}), F::FoldsBack);
  EXPECT_EQ(kind({{0, 0}, {1, 0}, {2, 0}}), F::None); // straight on
  EXPECT_EQ(kind({{0, 0}, {1, 0}, {-1, 0}}), F::FoldsBack);
  EXPECT_EQ(kind({{0, 0}, {1, 0}, {1, 1}, {0.5, -1}}), F::Intersects);
  EXPECT_EQ(kind({{0, 0}, {1, 0}, {1, 1}, {0, 0}}), F::Intersects);   // closed
  EXPECT_EQ(kind({{0, 0}, {1, 0}, {1, 1}, {0.5, 0}}), F::Intersects); // touches
  const F f = findFault(Crack{{{0, 0}, {1, 0}, {1, 1}, {0.5, 1}, {0.5, -1}}, {false, false}}, 1e-9);
  EXPECT_EQ(f.kind, F::Intersects);
  EXPECT_EQ(f.i, 0);
  EXPECT_EQ(f.j, 3);
}

} // namespace
