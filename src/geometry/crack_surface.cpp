#include "gimp/geometry/crack_surface.hpp"

#include "gimp/geometry/crack.hpp"

#include <algorithm>
#include <cmath>

namespace gimp::cracks {

namespace {

using P3 = std::array<double, 3>;
using P2 = std::array<double, 2>;

P3 sub(const P3 &a, const P3 &b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double dot(const double *a, const double *b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
P3 cross(const P3 &a, const P3 &b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const P3 &a) {
  return std::sqrt(dot(a.data(), a.data()));
}
double norm1(const double *a, const double *b) {
  return std::fabs(a[0] - b[0]) + std::fabs(a[1] - b[1]) + std::fabs(a[2] - b[2]);
}

/// Newell's normal of the vertices in their order (not normalised; zero for no area).
P3 newell(const std::vector<P3> &p) {
  P3 n{0, 0, 0};
  for (size_t i = 0; i < p.size(); ++i) {
    const P3 &a = p[i], &b = p[(i + 1) % p.size()];
    n[0] += (a[1] - b[1]) * (a[2] + b[2]);
    n[1] += (a[2] - b[2]) * (a[0] + b[0]);
    n[2] += (a[0] - b[0]) * (a[1] + b[1]);
  }
  return n;
}

P2 toPlane(const CrackSurface &c, const double x[3]) {
  const P3 r = {x[0] - c.origin[0], x[1] - c.origin[1], x[2] - c.origin[2]};
  return {dot(r.data(), c.e1.data()), dot(r.data(), c.e2.data())};
}

/// Where the point of the segment a-b nearest to q lies on it: a + s (b - a), s in [0, 1].
double segParam(const P2 &q, const P2 &a, const P2 &b) {
  const double dx = b[0] - a[0], dy = b[1] - a[1], L2 = dx * dx + dy * dy;
  const double s = L2 > 0 ? ((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / L2 : 0.0;
  return std::clamp(s, 0.0, 1.0);
}

/// Distance from q to the segment a-b in the plane.
double segDist2(const P2 &q, const P2 &a, const P2 &b) {
  const double s = segParam(q, a, b);
  return std::hypot(q[0] - a[0] - s * (b[0] - a[0]), q[1] - a[1] - s * (b[1] - a[1]));
}

/// Whether q is inside the polygon (crossing number; boundary undecided) and its distance to
/// the polygon's boundary; with `front`, its distance to the front edges alone.
bool inPolygon(const CrackSurface &c, const P2 &q, double &edgeDist, double *front = nullptr) {
  bool in = false;
  edgeDist = 1e300;
  if (front) *front = 1e300;
  const size_t m = c.uv.size();
  for (size_t i = 0, j = m - 1; i < m; j = i++) {
    const P2 &a = c.uv[i], &b = c.uv[j];
    if ((a[1] > q[1]) != (b[1] > q[1]) &&
        q[0] < (b[0] - a[0]) * (q[1] - a[1]) / (b[1] - a[1]) + a[0])
      in = !in;
    const double d = segDist2(q, a, b);
    edgeDist = std::min(edgeDist, d);
    if (front && j < c.front.size() && c.front[j]) *front = std::min(*front, d); // edge j: j -> i
  }
  return in;
}

} // namespace

CrackSurface makeSurface(const std::vector<P3> &points, const double *normalHint) {
  CrackSurface c;
  c.points = points;
  P3 n = newell(points);
  if (normalHint && dot(n.data(), normalHint) < 0) {
    std::reverse(c.points.begin(), c.points.end());
    n = {-n[0], -n[1], -n[2]};
  }
  const double len = norm(n);
  if (len > 0)
    for (double &v : n)
      v /= len;
  c.normal = n;
  c.origin = c.points[0];
  // e1 along the first edge, projected into the plane; e2 = n x e1.
  P3 e = sub(c.points[1 % c.points.size()], c.points[0]);
  const double en = dot(e.data(), n.data());
  for (int d = 0; d < 3; ++d)
    e[d] -= en * n[d];
  const double el = norm(e);
  for (double &v : e)
    v = el > 0 ? v / el : 0.0;
  c.e1 = e;
  c.e2 = cross(n, e);
  P3 lo = c.points[0], hi = c.points[0];
  for (const P3 &p : c.points) {
    c.uv.push_back(toPlane(c, p.data()));
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], p[d]);
      hi[d] = std::max(hi[d], p[d]);
    }
  }
  c.span = norm1(lo.data(), hi.data());
  c.front.assign(c.points.size(), 0);
  // The vertices' mean as the centre of the quick test's circles.
  for (const P2 &q : c.uv)
    for (int d = 0; d < 2; ++d)
      c.centre[d] += q[d] / static_cast<double>(c.uv.size());
  double edge = 0;
  const bool in = inPolygon(c, c.centre, edge);
  c.rIn = in ? edge : 0.0;
  for (const P2 &q : c.uv)
    c.rOut = std::max(c.rOut, std::hypot(q[0] - c.centre[0], q[1] - c.centre[1]));
  return c;
}

double planeDistance(const CrackSurface &c, const double x[3]) {
  const P3 r = {x[0] - c.origin[0], x[1] - c.origin[1], x[2] - c.origin[2]};
  return dot(r.data(), c.normal.data());
}

int crossing(const CrackSurface &c, const double a[3], const double b[3]) {
  const double delta = kCrackTol * (norm1(a, b) + c.span);
  const double da = planeDistance(c, a), db = planeDistance(c, b);
  const int sa = da >= -delta ? 1 : -1, sb = db >= -delta ? 1 : -1;
  if (sa == sb) return 0;
  // Where the segment meets the plane (the end on the plane when one is on it).
  const double t = std::clamp(da / (da - db), 0.0, 1.0);
  const double p[3] = {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]),
                       a[2] + t * (b[2] - a[2])};
  const P2 q = toPlane(c, p);
  const double r = std::hypot(q[0] - c.centre[0], q[1] - c.centre[1]);
  if (r < c.rIn - 2 * delta) return sa; // well inside: farther than delta from every edge
  if (r > c.rOut + 2 * delta) return 0; // outside
  double edge = 0, front = 0;
  const bool in = inPolygon(c, q, edge, &front);
  // Within delta of the boundary: outside at a front edge (the crack ends there), inside at a
  // mouth edge (it opens through the body's surface there).
  if (front <= delta) return 0;
  if (edge <= delta) return sa;
  return in ? sa : 0;
}

double distance(const CrackSurface &c, const double x[3]) {
  const double d = planeDistance(c, x);
  double edge = 0;
  if (inPolygon(c, toPlane(c, x), edge)) return std::fabs(d);
  return std::hypot(d, edge);
}

P3 nearestPoint(const CrackSurface &c, const double x[3]) {
  P2 q = toPlane(c, x);
  double edge = 0;
  if (!inPolygon(c, q, edge)) { // the nearest point of the nearest edge
    const size_t m = c.uv.size();
    double best = 1e300;
    P2 at = q;
    for (size_t i = 0, j = m - 1; i < m; j = i++) {
      const P2 &a = c.uv[j], &b = c.uv[i];
      const double s = segParam(q, a, b);
      const P2 p = {a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])};
      const double d = std::hypot(q[0] - p[0], q[1] - p[1]);
      if (d < best) {
        best = d;
        at = p;
      }
    }
    q = at;
  }
  P3 p{};
  for (int d = 0; d < 3; ++d)
    p[d] = c.origin[d] + q[0] * c.e1[d] + q[1] * c.e2[d];
  return p;
}

bool behindFront(const CrackSurface &c, const double x[3], double tol) {
  double edge = 0, front = 0;
  return inPolygon(c, toPlane(c, x), edge, &front) && front > tol;
}

int normalAt(const CrackSurface &c, const double *, double n[3]) {
  for (int d = 0; d < 3; ++d)
    n[d] = c.normal[d];
  return 0;
}

int sideOf(const CrackSurface &c, int, const double x[3]) {
  return planeDistance(c, x) >= -kCrackTol * c.span ? 1 : -1;
}

bool nearCrack(const CrackSurface &c, const double box[6], double reach) {
  const double mid[3] = {0.5 * (box[0] + box[3]), 0.5 * (box[1] + box[4]), 0.5 * (box[2] + box[5])};
  const double half = 0.5 * std::sqrt((box[3] - box[0]) * (box[3] - box[0]) +
                                      (box[4] - box[1]) * (box[4] - box[1]) +
                                      (box[5] - box[2]) * (box[5] - box[2]));
  return distance(c, mid) <= reach + half;
}

SurfaceFault findFault(const std::vector<P3> &points, double tol) {
  SurfaceFault f;
  const size_t m = points.size();
  if (m < 3) return {SurfaceFault::Degenerate, -1, -1};
  for (size_t i = 0; i < m; ++i)
    if (norm(sub(points[(i + 1) % m], points[i])) <= tol)
      return {SurfaceFault::ZeroLength, static_cast<int>(i), -1};
  const CrackSurface c = makeSurface(points);
  const P3 n = newell(points);
  if (norm(n) <= tol * tol) return {SurfaceFault::Degenerate, -1, -1};
  for (size_t i = 0; i < m; ++i)
    if (std::fabs(planeDistance(c, points[i].data())) > tol)
      return {SurfaceFault::NotPlanar, static_cast<int>(i), -1};
  // Edges i and j meet other than at a shared vertex (in the plane's coordinates).
  for (size_t i = 0; i < m; ++i)
    for (size_t j = 0; j < i; ++j) {
      const bool adjacent = i == j + 1 || (j == 0 && i == m - 1);
      const P2 &p0 = c.uv[i], &p1 = c.uv[(i + 1) % m], &q0 = c.uv[j], &q1 = c.uv[(j + 1) % m];
      double at[2];
      if (!adjacent) {
        if (segmentsMeet(p0, p1, q0, q1, at)) return {SurfaceFault::Intersects, int(i), int(j)};
        continue;
      }
      // Adjacent edges share one vertex; they fold back when the far end of one lies on the
      // other (or they overlap).
      const P2 &far = (i == j + 1) ? p1 : p0, &shared = (i == j + 1) ? p0 : p1;
      const P2 &otherFar = (i == j + 1) ? q0 : q1;
      if (segDist2(far, shared, otherFar) <= tol || segDist2(otherFar, shared, far) <= tol)
        return {SurfaceFault::Intersects, int(i), int(j)};
    }
  return f;
}

bool surfacesMeet(const CrackSurface &a, const CrackSurface &b, double at[3]) {
  for (int pass = 0; pass < 2; ++pass) {
    const CrackSurface &e = pass ? b : a, &s = pass ? a : b;
    const size_t m = e.points.size();
    const double tol = kCrackTol * (e.span + s.span);
    for (size_t i = 0; i < m; ++i) {
      const double *p = e.points[i].data(), *q = e.points[(i + 1) % m].data();
      const double dp = planeDistance(s, p), dq = planeDistance(s, q);
      if ((dp > tol && dq > tol) || (dp < -tol && dq < -tol)) continue;
      // The point of the edge on the plane (an end when it lies on the plane), or, for an edge
      // in the plane, the points along it.
      const bool inPlane = std::fabs(dp) <= tol && std::fabs(dq) <= tol;
      const int samples = inPlane ? 64 : 1;
      for (int k = 0; k <= samples; ++k) {
        const double t = inPlane
                             ? double(k) / samples
                             : std::clamp(std::fabs(dp) <= tol ? 0.0 : dp / (dp - dq), 0.0, 1.0);
        const double x[3] = {p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]),
                             p[2] + t * (q[2] - p[2])};
        double edge = 0;
        if (inPolygon(s, toPlane(s, x), edge) || edge <= tol) {
          for (int d = 0; d < 3; ++d)
            at[d] = x[d];
          return true;
        }
        if (!inPlane) break;
      }
    }
  }
  return false;
}

void frontFrame(const CrackSurface &c, int e, double a[3], double n[3], double t[3]) {
  const size_t m = c.points.size();
  P3 d = sub(c.points[(static_cast<size_t>(e) + 1) % m], c.points[static_cast<size_t>(e)]);
  const double L = norm(d);
  for (double &v : d)
    v /= L;
  const P3 ahead = cross(d, c.normal);
  for (int k = 0; k < 3; ++k) {
    t[k] = d[k];
    n[k] = c.normal[k];
    a[k] = ahead[k];
  }
}

int frontPieces(double length, double spacing) {
  return std::max(1, static_cast<int>(std::ceil(length / spacing - 1e-9)));
}

std::vector<FrontPoint> frontPoints(const CrackSurface &c, double spacing) {
  std::vector<FrontPoint> out;
  const size_t m = c.points.size();
  for (size_t e = 0; e < m; ++e) {
    if (!c.front[e]) continue;
    const P3 &p = c.points[e], &q = c.points[(e + 1) % m];
    const int pieces = frontPieces(norm(sub(q, p)), spacing);
    for (int k = 0; k < pieces; ++k) {
      FrontPoint f;
      f.edge = static_cast<int>(e);
      const double s = (k + 0.5) / pieces;
      for (int d = 0; d < 3; ++d)
        f.x[d] = p[d] + s * (q[d] - p[d]);
      frontFrame(c, static_cast<int>(e), f.a.data(), f.n.data(), f.t.data());
      out.push_back(f);
    }
  }
  return out;
}

} // namespace gimp::cracks
