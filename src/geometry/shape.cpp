// Plane shapes (see include/gimp/geometry/shape.hpp).
#include "gimp/geometry/shape.hpp"
#include "gimp/geometry/cut_cell.hpp"

#include <algorithm>
#include <cmath>

namespace gimp {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Twice the signed area of the polygon x0, y0, x1, y1, ... (positive counter-clockwise).
double twiceArea(const std::vector<double> &xy) {
  const size_t n = xy.size() / 2;
  double s = 0;
  for (size_t i = 0; i < n; ++i) {
    const size_t j = (i + 1) % n;
    s += xy[2 * i] * xy[2 * j + 1] - xy[2 * j] * xy[2 * i + 1];
  }
  return s;
}

double cross(double ax, double ay, double bx, double by) {
  return ax * by - ay * bx;
}

/// Whether the closed segments p1-p2 and q1-q2 meet.
bool segmentsMeet(const double *p1, const double *p2, const double *q1, const double *q2) {
  const double d1 = cross(q2[0] - q1[0], q2[1] - q1[1], p1[0] - q1[0], p1[1] - q1[1]);
  const double d2 = cross(q2[0] - q1[0], q2[1] - q1[1], p2[0] - q1[0], p2[1] - q1[1]);
  const double d3 = cross(p2[0] - p1[0], p2[1] - p1[1], q1[0] - p1[0], q1[1] - p1[1]);
  const double d4 = cross(p2[0] - p1[0], p2[1] - p1[1], q2[0] - p1[0], q2[1] - p1[1]);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
    return true;
  auto onSeg = [](const double *a, const double *b, const double *c) { // c on a-b, collinear
    return std::min(a[0], b[0]) <= c[0] && c[0] <= std::max(a[0], b[0]) &&
           std::min(a[1], b[1]) <= c[1] && c[1] <= std::max(a[1], b[1]);
  };
  return (d1 == 0 && onSeg(q1, q2, p1)) || (d2 == 0 && onSeg(q1, q2, p2)) ||
         (d3 == 0 && onSeg(p1, p2, q1)) || (d4 == 0 && onSeg(p1, p2, q2));
}

/// Distance from (x, y) to the segment a-b.
double segmentDistance(double x, double y, const double *a, const double *b) {
  const double ux = b[0] - a[0], uy = b[1] - a[1], len2 = ux * ux + uy * uy;
  const double t = len2 > 0 ? std::clamp(((x - a[0]) * ux + (y - a[1]) * uy) / len2, 0.0, 1.0) : 0;
  return std::hypot(x - a[0] - t * ux, y - a[1] - t * uy);
}

/// Raw moments {A, Sx, Sy, Sxx, Syy} of the rectangle [u0, u1] x [v0, v1] about the origin.
std::array<double, 5> rectangleMoments(double u0, double v0, double u1, double v1) {
  if (!(u1 > u0) || !(v1 > v0)) return {};
  const double w = u1 - u0, h = v1 - v0;
  return {w * h, 0.5 * (u1 * u1 - u0 * u0) * h, 0.5 * (v1 * v1 - v0 * v0) * w,
          (u1 * u1 * u1 - u0 * u0 * u0) / 3.0 * h, (v1 * v1 * v1 - v0 * v0 * v0) / 3.0 * w};
}

/// The polygon `poly` (x, y pairs) clipped to the half-plane s * (coordinate axis) <= s * c
/// (Sutherland-Hodgman; a non-convex polygon may leave zero-area bridges along the clip line,
/// which add nothing to the moments).
std::vector<double> clipHalfPlane(const std::vector<double> &poly, int axis, double c, double s) {
  std::vector<double> out;
  const size_t n = poly.size() / 2;
  out.reserve(poly.size() + 8);
  for (size_t i = 0; i < n; ++i) {
    const double *p = &poly[2 * i], *q = &poly[2 * ((i + 1) % n)];
    const double dp = s * (p[axis] - c), dq = s * (q[axis] - c);
    if (dp <= 0) out.insert(out.end(), {p[0], p[1]});
    if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0)) {
      const double t = dp / (dp - dq);
      double r[2] = {p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])};
      r[axis] = c; // exactly on the clip line
      out.insert(out.end(), {r[0], r[1]});
    }
  }
  return out;
}

/// Raw moments of a polygon (counter-clockwise) about the origin, by Green's theorem.
std::array<double, 5> polygonMoments(const std::vector<double> &xy) {
  std::array<double, 5> m{};
  const size_t n = xy.size() / 2;
  for (size_t i = 0; i < n; ++i) {
    const size_t j = (i + 1) % n;
    const double x0 = xy[2 * i], y0 = xy[2 * i + 1], x1 = xy[2 * j], y1 = xy[2 * j + 1];
    const double c = x0 * y1 - x1 * y0;
    m[0] += c;
    m[1] += (x0 + x1) * c;
    m[2] += (y0 + y1) * c;
    m[3] += (x0 * x0 + x0 * x1 + x1 * x1) * c;
    m[4] += (y0 * y0 + y0 * y1 + y1 * y1) * c;
  }
  m[0] /= 2.0;
  m[1] /= 6.0;
  m[2] /= 6.0;
  m[3] /= 12.0;
  m[4] /= 12.0;
  return m;
}

} // namespace

Shape Shape::rectangle(double x0, double y0, double x1, double y1) {
  Shape s;
  s.kind = Kind::Rectangle;
  s.box = {x0, y0, x1, y1};
  return s;
}

Shape Shape::ellipse(double cx, double cy, double a, double b) {
  Shape s;
  s.kind = Kind::Ellipse;
  s.cx = cx;
  s.cy = cy;
  s.a = a;
  s.b = b;
  s.box = {cx - a, cy - b, cx + a, cy + b};
  return s;
}

Shape Shape::polygon(const std::vector<double> &xy) {
  Shape s;
  s.kind = Kind::Polygon;
  s.xy = xy;
  if (twiceArea(xy) < 0) // store counter-clockwise
    for (size_t i = 0, n = xy.size() / 2; i < n; ++i) {
      s.xy[2 * i] = xy[2 * (n - 1 - i)];
      s.xy[2 * i + 1] = xy[2 * (n - 1 - i) + 1];
    }
  s.box = {xy[0], xy[1], xy[0], xy[1]};
  for (size_t i = 0; i + 1 < xy.size(); i += 2) {
    s.box[0] = std::min(s.box[0], xy[i]);
    s.box[1] = std::min(s.box[1], xy[i + 1]);
    s.box[2] = std::max(s.box[2], xy[i]);
    s.box[3] = std::max(s.box[3], xy[i + 1]);
  }
  return s;
}

bool Shape::contains(double x, double y) const {
  if (x < box[0] || x > box[2] || y < box[1] || y > box[3]) return false;
  switch (kind) {
  case Kind::Rectangle:
    return true;
  case Kind::Ellipse: {
    const double u = (x - cx) / a, v = (y - cy) / b;
    return u * u + v * v <= 1.0;
  }
  case Kind::Polygon: {
    const size_t n = xy.size() / 2;
    const double tol = 1e-12 * std::max(box[2] - box[0], box[3] - box[1]);
    bool in = false;
    for (size_t i = 0; i < n; ++i) {
      const double *p = &xy[2 * i], *q = &xy[2 * ((i + 1) % n)];
      if (segmentDistance(x, y, p, q) <= tol) return true; // on the boundary
      if ((p[1] > y) != (q[1] > y) && x < p[0] + (y - p[1]) * (q[0] - p[0]) / (q[1] - p[1]))
        in = !in;
    }
    return in;
  }
  }
  return false;
}

std::array<double, 5> Shape::momentsIn(double x0, double y0, double x1, double y1, double ox,
                                       double oy) const {
  // Nothing outside the bounding box.
  const double u0 = std::max(x0, box[0]) - ox, u1 = std::min(x1, box[2]) - ox;
  const double v0 = std::max(y0, box[1]) - oy, v1 = std::min(y1, box[3]) - oy;
  if (!(u1 > u0) || !(v1 > v0)) return {};
  switch (kind) {
  case Kind::Rectangle:
    return rectangleMoments(u0, v0, u1, v1);
  case Kind::Ellipse: {
    if (a == b)
      return cut::rectDiskMoments(x0 - ox, y0 - oy, x1 - ox, y1 - oy, cx - ox, cy - oy, a);
    // y' = k y with k = a / b maps the ellipse to the disk of radius a about (cx, k cy): the
    // moments scale by dA = dA' / k and y = y' / k.
    const double k = a / b;
    const auto m = cut::rectDiskMoments(x0 - ox, k * (y0 - oy), x1 - ox, k * (y1 - oy), cx - ox,
                                        k * (cy - oy), a);
    return {m[0] / k, m[1] / k, m[2] / (k * k), m[3] / k, m[4] / (k * k * k)};
  }
  case Kind::Polygon: {
    std::vector<double> poly(xy.size());
    for (size_t i = 0; i + 1 < xy.size(); i += 2) {
      poly[i] = xy[i] - ox;
      poly[i + 1] = xy[i + 1] - oy;
    }
    poly = clipHalfPlane(poly, 0, x1 - ox, 1.0);
    poly = clipHalfPlane(poly, 0, x0 - ox, -1.0);
    poly = clipHalfPlane(poly, 1, y1 - oy, 1.0);
    poly = clipHalfPlane(poly, 1, y0 - oy, -1.0);
    if (poly.size() < 6) return {};
    return polygonMoments(poly);
  }
  }
  return {};
}

std::vector<std::array<double, 2>> Shape::boundaryPoints(int n) const {
  std::vector<std::array<double, 2>> pts;
  switch (kind) {
  case Kind::Rectangle: {
    const double c[5][2] = {
        {box[0], box[1]}, {box[2], box[1]}, {box[2], box[3]}, {box[0], box[3]}, {box[0], box[1]}};
    for (int e = 0; e < 4; ++e)
      for (int i = 0; i < n / 4; ++i) {
        const double t = static_cast<double>(i) / (n / 4);
        pts.push_back(
            {c[e][0] + t * (c[e + 1][0] - c[e][0]), c[e][1] + t * (c[e + 1][1] - c[e][1])});
      }
    break;
  }
  case Kind::Ellipse:
    for (int i = 0; i < n; ++i) {
      const double t = 2.0 * kPi * i / n;
      pts.push_back({cx + a * std::cos(t), cy + b * std::sin(t)});
    }
    break;
  case Kind::Polygon: {
    const size_t m = xy.size() / 2;
    const int per = std::max(1, n / static_cast<int>(m));
    for (size_t i = 0; i < m; ++i) {
      const double *p = &xy[2 * i], *q = &xy[2 * ((i + 1) % m)];
      for (int s = 0; s < per; ++s) {
        const double t = static_cast<double>(s) / per;
        pts.push_back({p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])});
      }
    }
    break;
  }
  }
  return pts;
}

bool Shape::strictlyInside(double x, double y) const {
  const double tol = 1e-12 * std::max(box[2] - box[0], box[3] - box[1]);
  if (x <= box[0] + tol || x >= box[2] - tol || y <= box[1] + tol || y >= box[3] - tol)
    return false;
  switch (kind) {
  case Kind::Rectangle:
    return true;
  case Kind::Ellipse: {
    const double u = (x - cx) / a, v = (y - cy) / b;
    return u * u + v * v < 1.0 - 1e-12;
  }
  case Kind::Polygon: {
    const size_t n = xy.size() / 2;
    for (size_t i = 0; i < n; ++i)
      if (segmentDistance(x, y, &xy[2 * i], &xy[2 * ((i + 1) % n)]) <= tol) return false;
    return contains(x, y);
  }
  }
  return false;
}

bool insideOfUnion(const Shape &s, const std::vector<const Shape *> &parts) {
  for (const auto &p : s.boundaryPoints(720)) {
    bool in = false;
    for (const Shape *o : parts)
      in = in || o->contains(p[0], p[1]);
    if (!in) return false;
  }
  for (const Shape *o : parts)
    if (o->kind == Shape::Kind::Polygon)
      for (size_t v = 0; v + 1 < o->xy.size(); v += 2)
        if (s.strictlyInside(o->xy[v], o->xy[v + 1])) return false;
  return true;
}

bool Shape::insideOf(const Shape &outer) const {
  return insideOfUnion(*this, {&outer});
}

bool Shape::overlaps(const Shape &o) const {
  return interiorsMeet(
      box, o.box, [&] { return boundaryPoints(720); }, [&] { return o.boundaryPoints(720); },
      [&](double x, double y) { return strictlyInside(x, y); },
      [&](double x, double y) { return o.strictlyInside(x, y); });
}

namespace {

bool convexPolygon(const Shape &s) {
  if (s.kind != Shape::Kind::Polygon) return false;
  const size_t n = s.xy.size() / 2;
  for (size_t i = 0; i < n; ++i) { // counter-clockwise: every turn to the left (or straight)
    const double *a = &s.xy[2 * i], *b = &s.xy[2 * ((i + 1) % n)], *c = &s.xy[2 * ((i + 2) % n)];
    if (cross(b[0] - a[0], b[1] - a[1], c[0] - b[0], c[1] - b[1]) < 0) return false;
  }
  return true;
}

/// The polygon `poly` (coordinates relative to o) clipped to the left of the directed line
/// p -> q (Sutherland-Hodgman; exact intersections up to round-off).
std::vector<double> clipLeftOf(const std::vector<double> &poly, const double *p, const double *q) {
  std::vector<double> out;
  const size_t n = poly.size() / 2;
  const double ux = q[0] - p[0], uy = q[1] - p[1];
  auto side = [&](const double *v) { return -cross(ux, uy, v[0] - p[0], v[1] - p[1]); };
  for (size_t i = 0; i < n; ++i) {
    const double *a = &poly[2 * i], *b = &poly[2 * ((i + 1) % n)];
    const double da = side(a), db = side(b); // <= 0: left of the line (kept)
    if (da <= 0) out.insert(out.end(), {a[0], a[1]});
    if ((da < 0 && db > 0) || (da > 0 && db < 0)) {
      const double t = da / (da - db);
      out.insert(out.end(), {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])});
    }
  }
  return out;
}

} // namespace

bool intersectable(const Shape &a, const Shape &b) {
  return a.kind == Shape::Kind::Rectangle || b.kind == Shape::Kind::Rectangle ||
         (a.kind == Shape::Kind::Polygon && b.kind == Shape::Kind::Polygon &&
          (convexPolygon(a) || convexPolygon(b)));
}

std::array<double, 5> intersectionMomentsIn(const Shape &a, const Shape &b, double x0, double y0,
                                            double x1, double y1, double ox, double oy) {
  if (a.kind == Shape::Kind::Rectangle || b.kind == Shape::Kind::Rectangle) {
    const Shape &r = a.kind == Shape::Kind::Rectangle ? a : b, &o = &r == &a ? b : a;
    const double u0 = std::max(x0, r.box[0]), u1 = std::min(x1, r.box[2]);
    const double v0 = std::max(y0, r.box[1]), v1 = std::min(y1, r.box[3]);
    if (!(u1 > u0) || !(v1 > v0)) return {};
    return o.momentsIn(u0, v0, u1, v1, ox, oy);
  }
  // Two polygons, one convex: the other clipped by each of its edges, then by the rectangle.
  const Shape &cv = convexPolygon(a) ? a : b, &other = &cv == &a ? b : a;
  std::vector<double> poly(other.xy.size());
  for (size_t i = 0; i + 1 < other.xy.size(); i += 2) {
    poly[i] = other.xy[i] - ox;
    poly[i + 1] = other.xy[i + 1] - oy;
  }
  const size_t n = cv.xy.size() / 2;
  for (size_t i = 0; i < n && poly.size() >= 6; ++i) {
    const double p[2] = {cv.xy[2 * i] - ox, cv.xy[2 * i + 1] - oy};
    const double q[2] = {cv.xy[2 * ((i + 1) % n)] - ox, cv.xy[2 * ((i + 1) % n) + 1] - oy};
    poly = clipLeftOf(poly, p, q);
  }
  if (poly.size() < 6) return {};
  Shape clipped;
  clipped.kind = Shape::Kind::Polygon;
  clipped.xy = poly; // relative to o already
  clipped.box = {-1e300, -1e300, 1e300, 1e300};
  return clipped.momentsIn(x0 - ox, y0 - oy, x1 - ox, y1 - oy, 0.0, 0.0);
}

std::string polygonProblem(const std::vector<double> &xy) {
  if (xy.size() % 2) return "needs pairs x,y";
  if (xy.size() < 6) return "needs at least 3 vertices";
  for (double v : xy)
    if (!std::isfinite(v)) return "needs finite coordinates";
  const size_t n = xy.size() / 2;
  for (size_t i = 0; i < n; ++i) {
    const size_t j = (i + 1) % n;
    if (xy[2 * i] == xy[2 * j] && xy[2 * i + 1] == xy[2 * j + 1])
      return "has a repeated vertex (" + std::to_string(i) + " and " + std::to_string(j) + ")";
  }
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) {
      if (j == i + 1 || (i == 0 && j == n - 1)) { // neighbours share a vertex only
        const size_t shared = j == i + 1 ? j : i;
        const size_t pi = j == i + 1 ? i : j, pj = j == i + 1 ? (j + 1) % n : 1;
        // Collinear and folding back: the far vertex of one edge lies on the other.
        const double *s = &xy[2 * shared], *a = &xy[2 * pi], *b = &xy[2 * pj];
        if (cross(a[0] - s[0], a[1] - s[1], b[0] - s[0], b[1] - s[1]) == 0 &&
            (a[0] - s[0]) * (b[0] - s[0]) + (a[1] - s[1]) * (b[1] - s[1]) > 0)
          return "folds back on itself at vertex " + std::to_string(shared);
        continue;
      }
      if (segmentsMeet(&xy[2 * i], &xy[2 * ((i + 1) % n)], &xy[2 * j], &xy[2 * ((j + 1) % n)]))
        return "crosses itself (edges " + std::to_string(i) + " and " + std::to_string(j) + ")";
    }
  if (twiceArea(xy) == 0) return "has zero area";
  return "";
}

} // namespace gimp
