// Crack geometry: the crossing test of the stencils, distances, normals and the validation of
// a polyline (see include/gimp/geometry/crack.hpp for the conventions and the tolerance).
#include "gimp/geometry/crack.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gimp::cracks {

namespace {

using Point = std::array<double, 2>;

inline double cross(double ux, double uy, double vx, double vy) {
  return ux * vy - uy * vx;
}

/// Distance from (x, y) to the segment p-q.
double pointSegment(double x, double y, const Point &p, const Point &q) {
  const double tx = q[0] - p[0], ty = q[1] - p[1], rx = x - p[0], ry = y - p[1];
  const double tt = tx * tx + ty * ty;
  const double s = tt > 0 ? std::clamp((rx * tx + ry * ty) / tt, 0.0, 1.0) : 0.0;
  return std::hypot(rx - s * tx, ry - s * ty);
}

/// The segment a-b as crossing() sees it: its canonical origin c (the lexicographically smaller
/// of a, b) and direction d = (the other) - c, and its length.
struct Query {
  double ax, ay, bx, by, cx, cy, dx, dy, len;
};

/// Side of crack vertex k relative to the line a-b, taken in the canonical direction: +1 left,
/// -1 right. A vertex on the line (within delta) takes the side of its perturbed position: an end
/// point is moved inwards along the crack (0: the segment is not crossed there), an interior
/// vertex along its mitre to the right (the sign of cross(d, m)); +1 when d runs along m.
int vertexSide(const Crack &c, size_t k, const Query &q) {
  const Point &v = c.points[k];
  const double e = cross(q.dx, q.dy, v[0] - q.cx, v[1] - q.cy);
  const double reach = std::fabs(v[0] - q.cx) + std::fabs(v[1] - q.cy);
  if (std::fabs(e) > kCrackTol * (q.len + reach) * q.len) return e > 0 ? 1 : -1;
  if (k == 0 || k + 1 == c.points.size()) return 0;
  // Unit left normals of the two segments at v; the mitre points right: m = -(n0 + n1).
  const Point &u = c.points[k - 1], &w = c.points[k + 1];
  const double l0 = std::hypot(v[0] - u[0], v[1] - u[1]), l1 = std::hypot(w[0] - v[0], w[1] - v[1]);
  const double mx = (v[1] - u[1]) / l0 + (w[1] - v[1]) / l1;
  const double my = -(v[0] - u[0]) / l0 - (w[0] - v[0]) / l1;
  const double s = cross(q.dx, q.dy, mx, my);
  if (std::fabs(s) > kCrackTol * q.len * std::hypot(mx, my)) return s > 0 ? 1 : -1;
  return 1;
}

} // namespace

namespace {

/// crossing() over the segments seg(0) .. seg(n - 1) of c (in increasing order); any segment
/// left out must fail the box test below.
template <class Seg>
int crossingOver(const Crack &c, Seg seg, size_t n, double ax, double ay, double bx, double by) {
  const double len = std::sqrt((bx - ax) * (bx - ax) + (by - ay) * (by - ay));
  if (!(len > 0) || c.points.size() < 2) return 0;
  const bool aFirst = ax < bx || (ax == bx && ay < by);
  Query q{ax, ay, bx, by, aFirst ? ax : bx, aFirst ? ay : by, 0, 0, len};
  q.dx = (aFirst ? bx : ax) - q.cx;
  q.dy = (aFirst ? by : ay) - q.cy;
  const double xlo = std::min(ax, bx), xhi = std::max(ax, bx);
  const double ylo = std::min(ay, by), yhi = std::max(ay, by);
  int count = 0, side = 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < n; ++i) {
    const size_t k = seg(i);
    const Point &p = c.points[k], &r = c.points[k + 1];
    const double tx = r[0] - p[0], ty = r[1] - p[1];
    const double lpq = std::fabs(tx) + std::fabs(ty); // |pq| in the 1-norm
    const double delta = kCrackTol * (len + lpq);
    if (std::min(p[0], r[0]) > xhi + delta || std::max(p[0], r[0]) < xlo - delta ||
        std::min(p[1], r[1]) > yhi + delta || std::max(p[1], r[1]) < ylo - delta)
      continue;
    // Sides of a and b: on the line (within delta) counts as left.
    const double da = cross(tx, ty, ax - p[0], ay - p[1]);
    const double db = cross(tx, ty, bx - p[0], by - p[1]);
    const double onLine = delta * std::sqrt(tx * tx + ty * ty);
    const int sa = da >= -onLine ? 1 : -1, sb = db >= -onLine ? 1 : -1;
    if (sa == sb) continue;
    // Does the line a-b pass between p and r?
    const int sp = vertexSide(c, k, q), sr = vertexSide(c, k + 1, q);
    if (sp == 0 || sr == 0 || sp == sr) continue;
    ++count;
    const double t = da / (da - db); // where a->b meets the segment's line, from a
    if (t < nearest) {
      nearest = t;
      side = sa;
    }
  }
  return count % 2 ? side : 0;
}

} // namespace

int crossing(const Crack &c, double ax, double ay, double bx, double by) {
  const size_t n = c.points.size() < 2 ? 0 : c.points.size() - 1;
  return crossingOver(
      c, [](size_t i) { return i; }, n, ax, ay, bx, by);
}

void segmentsNear(const Crack &c, const double box[4], std::vector<int> &out) {
  out.clear();
  const double span = (box[2] - box[0]) + (box[3] - box[1]);
  for (size_t k = 0; k + 1 < c.points.size(); ++k) {
    const Point &p = c.points[k], &r = c.points[k + 1];
    const double m = 1e-6 * (span + std::fabs(r[0] - p[0]) + std::fabs(r[1] - p[1]));
    if (std::min(p[0], r[0]) > box[2] + m || std::max(p[0], r[0]) < box[0] - m ||
        std::min(p[1], r[1]) > box[3] + m || std::max(p[1], r[1]) < box[1] - m)
      continue;
    out.push_back(static_cast<int>(k));
  }
}

int crossing(const Crack &c, const std::vector<int> &segs, double ax, double ay, double bx,
             double by) {
  return crossingOver(
      c, [&](size_t i) { return static_cast<size_t>(segs[i]); }, segs.size(), ax, ay, bx, by);
}

double distance(const Crack &c, double x, double y) {
  double d = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k + 1 < c.points.size(); ++k)
    d = std::min(d, pointSegment(x, y, c.points[k], c.points[k + 1]));
  return d;
}

int normalAt(const Crack &c, double x, double y, double n[2]) {
  if (c.points.size() < 2) {
    n[0] = n[1] = 0;
    return -1;
  }
  double best = std::numeric_limits<double>::infinity();
  int nearest = 0;
  for (size_t k = 0; k + 1 < c.points.size(); ++k) {
    const double d = pointSegment(x, y, c.points[k], c.points[k + 1]);
    if (d < best) {
      best = d;
      nearest = static_cast<int>(k);
    }
  }
  const Point &p = c.points[nearest], &r = c.points[nearest + 1];
  const double l = std::hypot(r[0] - p[0], r[1] - p[1]);
  n[0] = -(r[1] - p[1]) / l;
  n[1] = (r[0] - p[0]) / l;
  return nearest;
}

int sideOf(const Crack &c, int seg, double x, double y) {
  const Point &p = c.points[seg], &r = c.points[seg + 1];
  const double tx = r[0] - p[0], ty = r[1] - p[1];
  const double delta = kCrackTol * (std::fabs(tx) + std::fabs(ty));
  return cross(tx, ty, x - p[0], y - p[1]) >= -delta * std::sqrt(tx * tx + ty * ty) ? 1 : -1;
}

double segmentDistance(const Point &p0, const Point &p1, const Point &q0, const Point &q1) {
  const double ux = p1[0] - p0[0], uy = p1[1] - p0[1], vx = q1[0] - q0[0], vy = q1[1] - q0[1];
  const double a = cross(ux, uy, q0[0] - p0[0], q0[1] - p0[1]);
  const double b = cross(ux, uy, q1[0] - p0[0], q1[1] - p0[1]);
  const double e = cross(vx, vy, p0[0] - q0[0], p0[1] - q0[1]);
  const double f = cross(vx, vy, p1[0] - q0[0], p1[1] - q0[1]);
  if (((a > 0 && b < 0) || (a < 0 && b > 0)) && ((e > 0 && f < 0) || (e < 0 && f > 0))) return 0;
  return std::min({pointSegment(q0[0], q0[1], p0, p1), pointSegment(q1[0], q1[1], p0, p1),
                   pointSegment(p0[0], p0[1], q0, q1), pointSegment(p1[0], p1[1], q0, q1)});
}

bool nearCrack(const Crack &c, const double box[4], double reach) {
  const Point corner[4] = {{box[0], box[1]}, {box[2], box[1]}, {box[2], box[3]}, {box[0], box[3]}};
  for (size_t k = 0; k + 1 < c.points.size(); ++k) {
    const Point &p = c.points[k], &r = c.points[k + 1];
    if (std::min(p[0], r[0]) > box[2] + reach || std::max(p[0], r[0]) < box[0] - reach ||
        std::min(p[1], r[1]) > box[3] + reach || std::max(p[1], r[1]) < box[1] - reach)
      continue;
    // A segment that reaches into the box passes through it or crosses an edge.
    if (p[0] >= box[0] && p[0] <= box[2] && p[1] >= box[1] && p[1] <= box[3]) return true;
    for (int e = 0; e < 4; ++e)
      if (segmentDistance(p, r, corner[e], corner[(e + 1) % 4]) <= reach) return true;
  }
  return false;
}

namespace {

/// Side of x relative to the line a-b: +1 left, -1 right, 0 within delta of the line.
int lineSide(const Point &a, const Point &b, const Point &x, double delta) {
  const double tx = b[0] - a[0], ty = b[1] - a[1];
  const double o = cross(tx, ty, x[0] - a[0], x[1] - a[1]);
  if (std::fabs(o) <= delta * std::sqrt(tx * tx + ty * ty)) return 0;
  return o > 0 ? 1 : -1;
}

/// Where x falls along a-b: 0 at a, 1 at b.
double along(const Point &a, const Point &b, const Point &x) {
  const double tx = b[0] - a[0], ty = b[1] - a[1];
  return ((x[0] - a[0]) * tx + (x[1] - a[1]) * ty) / (tx * tx + ty * ty);
}

/// Whether x, on the line of a-b (within delta), lies between a and b (within delta).
bool between(const Point &a, const Point &b, const Point &x, double delta) {
  const double s = along(a, b, x), e = delta / std::hypot(b[0] - a[0], b[1] - a[1]);
  return s >= -e && s <= 1.0 + e;
}

} // namespace

int segmentsMeet(const Point &p0, const Point &p1, const Point &q0, const Point &q1, double at[2]) {
  const double delta = kCrackTol * (std::fabs(p1[0] - p0[0]) + std::fabs(p1[1] - p0[1]) +
                                    std::fabs(q1[0] - q0[0]) + std::fabs(q1[1] - q0[1]));
  const int s1 = lineSide(p0, p1, q0, delta), s2 = lineSide(p0, p1, q1, delta);
  const int s3 = lineSide(q0, q1, p0, delta), s4 = lineSide(q0, q1, p1, delta);
  if (s1 * s2 > 0 || s3 * s4 > 0) return 0; // one segment wholly on one side of the other's line
  if (s1 && s2 && s3 && s4) {               // a proper crossing: where q meets p's line
    const double d1 = cross(p1[0] - p0[0], p1[1] - p0[1], q0[0] - p0[0], q0[1] - p0[1]);
    const double d2 = cross(p1[0] - p0[0], p1[1] - p0[1], q1[0] - p0[0], q1[1] - p0[1]);
    const double t = d1 / (d1 - d2);
    at[0] = q0[0] + t * (q1[0] - q0[0]);
    at[1] = q0[1] + t * (q1[1] - q0[1]);
    return 2;
  }
  // An end point on the other segment's line touches when it lies between that segment's ends
  // (collinear segments: when one's end lies on the other, which is what overlap means).
  const Point *ends[4][3] = {{&q0, &p0, &p1}, {&q1, &p0, &p1}, {&p0, &q0, &q1}, {&p1, &q0, &q1}};
  const int sides[4] = {s1, s2, s3, s4};
  for (int e = 0; e < 4; ++e)
    if (sides[e] == 0 && between(*ends[e][1], *ends[e][2], *ends[e][0], delta)) {
      at[0] = (*ends[e][0])[0];
      at[1] = (*ends[e][0])[1];
      return 1;
    }
  return 0;
}

int cracksMeet(const Crack &a, const Crack &b, double at[2]) {
  for (size_t i = 0; i + 1 < a.points.size(); ++i)
    for (size_t j = 0; j + 1 < b.points.size(); ++j)
      if (const int m =
              segmentsMeet(a.points[i], a.points[i + 1], b.points[j], b.points[j + 1], at))
        return m;
  return 0;
}

PolylineFault findFault(const Crack &c, double tol) {
  const auto &x = c.points;
  const int n = static_cast<int>(x.size()) - 1; // segments
  for (int i = 0; i < n; ++i)
    if (std::hypot(x[i + 1][0] - x[i][0], x[i + 1][1] - x[i][1]) <= tol)
      return {PolylineFault::ZeroLength, i, i + 1};
  for (int i = 0; i + 1 < n; ++i)
    if (pointSegment(x[i + 2][0], x[i + 2][1], x[i], x[i + 1]) <= tol ||
        pointSegment(x[i][0], x[i][1], x[i + 1], x[i + 2]) <= tol)
      return {PolylineFault::FoldsBack, i, i + 1};
  for (int i = 0; i < n; ++i)
    for (int j = i + 2; j < n; ++j)
      if (segmentDistance(x[i], x[i + 1], x[j], x[j + 1]) <= tol)
        return {PolylineFault::Intersects, i, j};
  return {};
}

} // namespace gimp::cracks
