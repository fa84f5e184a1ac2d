// The J-integral's domain at each crack tip (docs/method.md, *Crack tips*): the radius asked for
// (-gimp_crack_j_radius, or kJCells cells at the tip) against the tip's clearance, the distance
// to the nearest thing a valid domain may not reach: the edge of the tip's body (its shape's
// boundary, its holes), the grid's edge, another crack, the rest of its own crack (past a kink,
// or its other tip). A given radius is refused when no domain fits the tip, when it is under
// kJMinCells cells there, or when it is larger than the body; a radius past the clearance is
// clipped to it with a warning; the default radius is clipped alike, and a tip where no domain
// fits measures no J (a warning).
#include "scene_options.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gimp {
namespace input {

namespace {

using Point = std::array<double, 2>;

/// Distance from x to the segment a-b.
double toSegment(const Point &x, const Point &a, const Point &b) {
  return cracks::segmentDistance(a, b, x, x);
}

/// Distance from x to the boundary of a shape (an ellipse that is not a circle: to 2^14 points on
/// it, within a 2^-15 of its perimeter).
double toBoundary(const Shape &s, const Point &x) {
  double d = std::numeric_limits<double>::infinity();
  if (s.kind == Shape::Kind::Ellipse && s.a == s.b)
    return std::fabs(std::hypot(x[0] - s.cx, x[1] - s.cy) - s.a);
  if (s.kind == Shape::Kind::Ellipse) {
    for (const Point &p : s.boundaryPoints(1 << 14))
      d = std::min(d, std::hypot(p[0] - x[0], p[1] - x[1]));
    return d;
  }
  std::vector<Point> v;
  if (s.kind == Shape::Kind::Rectangle)
    v = {{s.box[0], s.box[1]}, {s.box[2], s.box[1]}, {s.box[2], s.box[3]}, {s.box[0], s.box[3]}};
  else
    for (size_t i = 0; i + 1 < s.xy.size(); i += 2)
      v.push_back({s.xy[i], s.xy[i + 1]});
  for (size_t i = 0; i < v.size(); ++i)
    d = std::min(d, toSegment(x, v[i], v[(i + 1) % v.size()]));
  return d;
}

/// Distance from x (in the body) to the body's edge: its shape's boundary (a union's: the
/// points of its parts' boundaries, 2^14 each, that no other part holds strictly inside), its
/// holes' boundaries. A body from a particle file: its shape, the particles' bounding box.
double bodyClearance(const Body<2> &b, const Point &x) {
  double d = std::numeric_limits<double>::infinity();
  const std::vector<const Shape *> parts = b.parts();
  if (parts.size() == 1) d = toBoundary(b.shape, x);
  for (size_t i = 0; parts.size() > 1 && i < parts.size(); ++i)
    for (const Point &p : parts[i]->boundaryPoints(1 << 14)) {
      bool covered = false;
      for (size_t j = 0; j < parts.size(); ++j)
        covered = covered || (j != i && parts[j]->strictlyInside(p[0], p[1]));
      if (!covered) d = std::min(d, std::hypot(p[0] - x[0], p[1] - x[1]));
    }
  for (const Hole &c : b.holes)
    d = std::min(d, std::fabs(std::hypot(x[0] - c.cx, x[1] - c.cy) - c.r));
  for (const Shape &h : b.shapeHoles)
    d = std::min(d, toBoundary(h, x));
  return d;
}

/// The diagonal of the bounding box of the body's shapes [m].
double bodySize(const Body<2> &b) {
  std::array<double, 4> box = b.shape.box;
  for (const Shape &s : b.added)
    box = {std::min(box[0], s.box[0]), std::min(box[1], s.box[1]), std::max(box[2], s.box[2]),
           std::max(box[3], s.box[3])};
  return std::hypot(box[2] - box[0], box[3] - box[1]);
}

/// The cell at x: the finest level whose open box holds it, as the grid finds a tip's level.
double tipCell(const Scene<2> &sc, const Point &x) {
  double h = sc.h, at = sc.h;
  for (size_t k = 1; k < sc.levels.size(); ++k) {
    const BoxOf<2> &b = sc.levels[k].box;
    h /= sc.levels[k].ratio;
    if (x[0] > b[0] && x[0] < b[2] && x[1] > b[1] && x[1] < b[3]) at = h;
  }
  return at;
}

/// One tip's clearance, what limits it, and the size of its body.
struct TipClearance : Clearance {
  double bodySize = std::numeric_limits<double>::infinity();
  std::string body;
};

/// The part of crack c from its first kink seen from end e on (the points in order from the tip;
/// a vertex where the crack runs on in the tip segment's direction, within kCrackTol, is no
/// kink); no points when it has none.
Crack pastTheKink(const Crack &c, int e) {
  std::vector<Point> p = c.points;
  if (e) std::reverse(p.begin(), p.end());
  const double tx = p[1][0] - p[0][0], ty = p[1][1] - p[0][1], lt = std::hypot(tx, ty);
  Crack rest;
  for (size_t v = 1; v + 1 < p.size(); ++v) {
    const double sx = p[v + 1][0] - p[v][0], sy = p[v + 1][1] - p[v][1];
    const double ls = std::hypot(sx, sy);
    if (std::fabs(tx * sy - ty * sx) <= cracks::kCrackTol * lt * ls && tx * sx + ty * sy > 0)
      continue;
    rest.points.assign(p.begin() + static_cast<std::ptrdiff_t>(v), p.end());
    break;
  }
  return rest;
}

TipClearance tipClearance(const Scene<2> &sc, size_t k, int e) {
  const Crack &c = sc.cracks[k];
  const Point x = e ? c.points.back() : c.points.front();
  TipClearance r;
  for (size_t i = 0; i < sc.bodies.size(); ++i)
    if (sc.bodies[i].inside(x[0], x[1])) {
      r.body = "body " + std::to_string(i);
      r.take(bodyClearance(sc.bodies[i], x), "the edge of " + r.body);
      r.bodySize = bodySize(sc.bodies[i]);
      break;
    }
  const BoxOf<2> &g = sc.domain;
  r.take(std::min({x[0] - g[0], g[2] - x[0], x[1] - g[1], g[3] - x[1]}), "the grid's edge");
  for (size_t m = 0; m < sc.cracks.size(); ++m)
    if (m != k) r.take(cracks::distance(sc.cracks[m], x[0], x[1]), "crack " + std::to_string(m));
  // Its own crack from its first kink on, and its other end when that is a tip. The kinks that
  // growth made are not counted: the crack as given, without its grown points, is searched.
  Crack given = c;
  given.points.assign(c.points.begin() + c.grown[0], c.points.end() - c.grown[1]);
  const Crack rest = pastTheKink(given, e);
  if (rest.points.size() > 1) r.take(cracks::distance(rest, x[0], x[1]), "its own crack's kink");
  const Point &o = e ? c.points.front() : c.points.back();
  if (c.tip[1 - e]) r.take(std::hypot(o[0] - x[0], o[1] - x[1]), "its crack's other tip");
  return r;
}

std::string tipName(const Point &x, size_t k) {
  return "the tip " + formatNumber(x[0]) + "," + formatNumber(x[1]) + " of crack " +
         std::to_string(k);
}

/// A given radius R that no domain at the tip can take is refused.
void checkGiven(double R, double h, const TipClearance &c, const std::string &tip) {
  const std::string opt = "gimp_crack_j_radius", val = formatNumber(R);
  const double lo = kJMinCells * h;
  if (c.d < lo)
    Options::bad(opt, val,
                 "no domain fits at " + tip + ": it is " + formatNumber(c.d) + " m from " + c.what +
                     ", less than 2 cells (" + formatNumber(lo) +
                     " m); without the option J is not measured there");
  const std::string range = "valid there: " + formatNumber(lo) + " m (2 cells) to " +
                            formatNumber(c.d) + " m (" + c.what + ")";
  if (!(R >= lo))
    Options::bad(opt, val,
                 "under 2 cells (cell " + formatNumber(h) + " m) at " + tip + "; " + range);
  if (R > c.bodySize)
    Options::bad(opt, val,
                 "larger than " + c.body + " (" + formatNumber(c.bodySize) + " m across) at " +
                     tip + "; " + range);
}

void warn(const std::string &line) {
  PetscCallAbort(PETSC_COMM_WORLD,
                 PetscPrintf(PETSC_COMM_WORLD, "gimp: warning: %s\n", line.c_str()));
}

} // namespace

namespace {

/// The J domains of every tip; quiet: after growth, no warnings and no refusals.
void jDomains(Scene<2> &sc, bool radiusGiven, bool quiet) {
  sc.jDomain.clear();
  for (size_t k = 0; k < sc.cracks.size(); ++k)
    for (int e = 0; e < 2; ++e) {
      const Crack &c = sc.cracks[k];
      if (!c.tip[e]) continue;
      const Point x = e ? c.points.back() : c.points.front();
      const double h = tipCell(sc, x);
      const double R = radiusGiven ? sc.crackJRadius : kJCells * h;
      const TipClearance cl = tipClearance(sc, k, e);
      const std::string tip = tipName(x, k);
      if (radiusGiven && !quiet) checkGiven(R, h, cl, tip);
      JDomain j{R, false};
      if (cl.d < kJMinCells * h) {
        j.radius = 0;
        if (!quiet)
          warn(tip + " is " + formatNumber(cl.d) + " m from " + cl.what + ", less than 2 cells (" +
               formatNumber(kJMinCells * h) +
               " m): no J domain fits, G_J, KI_J and KII_J are not measured there (null in "
               "summary.json)");
      } else if (R > cl.d) {
        j = {cl.d, true};
        if (quiet) {
          sc.jDomain.push_back(j);
          continue;
        }
        const std::string asked = radiusGiven
                                      ? "option -gimp_crack_j_radius " + formatNumber(R)
                                      : "the default J radius " + formatNumber(R) + " m (5 cells)";
        warn(asked + " at " + tip + " reaches " + cl.what + " (" + formatNumber(cl.d) +
             " m away): its J domain is clipped to " + formatNumber(cl.d) +
             " m (j_domain_clipped in summary.json)");
      }
      sc.jDomain.push_back(j);
    }
}

} // namespace

void setJDomains(Scene<2> &sc, bool radiusGiven) {
  jDomains(sc, radiusGiven, false);
}

} // namespace input

void updateJDomains(Scene<2> &sc) {
  input::jDomains(sc, sc.crackJRadius > 0, true);
}

} // namespace gimp
