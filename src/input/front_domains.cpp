// The tubes of the front integrals at each 3D front point (docs/method.md, *3D cracks*): the
// radius asked for (-gimp_crack_j_radius, or kJCells cells at the front) against the point's
// clearance, the distance from the piece of its front chain that its tube follows (arc length
// within L = R of the point) to the nearest thing a valid tube may not reach:
//   - a surface of a body or of a hole (a box's or a box hole's faces one by one, a sphere, a
//     cylinder's side and each of its ends), unless an end of one of the crack's front chains lies
//     on it: that surface is crossed by the front, where the tube takes the mirror images across
//     a symmetry plane or meets a free surface at the front's end (the grid's edge lies beyond
//     the bodies' surfaces);
//   - another crack;
//   - its own crack's front reached only the long way round (or on another chain): a narrow
//     crack's other side, a penny crack's far side; the tube's weight would jump at the bisector
//     between them, so half the distance counts.
// The chain's piece is sampled at a quarter of the cell at the front and at its vertices. A given
// radius is refused when no tube fits a front point (under kJMinCells cells there), and when it is
// under kJMinCells cells; a radius past a clearance is clipped to it at that point, with one
// warning per crack; the default radius is clipped alike, and a point where no tube fits is not
// measured (a warning). The result, per front point in measureFronts' order, is Scene::jDomain.
#include "scene_options.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace gimp {
namespace input {

namespace {

using P3 = std::array<double, 3>;

double dist(const P3 &a, const P3 &b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

/// A surface a tube may not reach, unless the front crosses it: its name and the distance to it.
struct Surface {
  std::string name;
  std::function<double(const P3 &)> distance;
};

/// Distance from x to the face x_axis = coord of box b (the face's rectangle).
double toFace(const P3 &x, const BoxOf<3> &b, int axis, double coord) {
  double s = (x[static_cast<size_t>(axis)] - coord) * (x[static_cast<size_t>(axis)] - coord);
  for (int q = 0; q < 3; ++q) {
    if (q == axis) continue;
    const double v = x[static_cast<size_t>(q)];
    const double out = std::max({b[q] - v, 0.0, v - b[3 + q]});
    s += out * out;
  }
  return std::sqrt(s);
}

/// The six faces of box b, named "<what>'s face x-" and so on.
void addFaces(std::vector<Surface> &out, const BoxOf<3> &b, const std::string &what) {
  const char *side[6] = {"x-", "y-", "z-", "x+", "y+", "z+"};
  for (int f = 0; f < 6; ++f) {
    const int axis = f % 3;
    const double coord = b[f];
    out.push_back({what + "'s face " + side[f],
                   [b, axis, coord](const P3 &x) { return toFace(x, b, axis, coord); }});
  }
}

/// The surfaces of a sphere or a cylinder (its side, and its ends unless `through`).
void addRound(std::vector<Surface> &out, const Solid &s, const std::string &what, bool through) {
  if (s.kind == Solid::Sphere) {
    out.push_back({what, [s](const P3 &x) {
                     return std::fabs(dist(x, {s.c[0], s.c[1], s.c[2]}) - s.r);
                   }});
    return;
  }
  const size_t a = static_cast<size_t>(s.axis), u = (a + 1) % 3, v = (a + 2) % 3;
  const auto radial = [s, u, v](const P3 &x) { return std::hypot(x[u] - s.c[u], x[v] - s.c[v]); };
  const double lo = through ? -INFINITY : s.lo, hi = through ? INFINITY : s.hi;
  out.push_back({what + "'s side", [=](const P3 &x) {
                   const double dz = std::max({lo - x[a], 0.0, x[a] - hi});
                   return std::hypot(radial(x) - s.r, dz);
                 }});
  if (through) return;
  for (const double end : {lo, hi})
    out.push_back({what + "'s end at " + formatNumber(end), [=](const P3 &x) {
                     return std::hypot(x[a] - end, std::max(radial(x) - s.r, 0.0));
                   }});
}

std::vector<Surface> surfacesOf(const Scene<3> &sc) {
  std::vector<Surface> out;
  for (size_t i = 0; i < sc.bodies.size(); ++i) {
    const Body<3> &b = sc.bodies[i];
    const std::string name = "body " + std::to_string(i);
    if (b.kind == Body<3>::BoxShape)
      addFaces(out, b.box, name);
    else
      addRound(out, b.round, name, false);
    for (size_t k = 0; k < b.holes.size(); ++k) {
      const Solid &h = b.holes[k];
      const std::string hole = "hole " + std::to_string(k) + " of " + name;
      if (h.kind == Solid::BoxHole)
        addFaces(out, h.b, hole);
      else
        addRound(out, h, hole, h.kind == Solid::Cylinder);
    }
  }
  return out;
}

/// The chains of consecutive front edges of crack c: each its edges in order and whether it is
/// closed.
struct Chain {
  std::vector<int> edges;
  bool closed = false;
};

std::vector<Chain> chainsOf(const CrackSurface &c) {
  const int m = static_cast<int>(c.points.size());
  std::vector<Chain> out;
  if (std::all_of(c.front.begin(), c.front.end(), [](char e) { return e != 0; })) {
    Chain ch{{}, true};
    for (int e = 0; e < m; ++e)
      ch.edges.push_back(e);
    return {ch};
  }
  for (int e = 0; e < m; ++e) {
    if (!c.front[static_cast<size_t>(e)] || c.front[static_cast<size_t>((e + m - 1) % m)]) continue;
    Chain ch;
    for (int k = e; c.front[static_cast<size_t>(k)]; k = (k + 1) % m)
      ch.edges.push_back(k);
    out.push_back(ch);
  }
  return out;
}

/// A point of a front chain: where, its chain and its arc length along it.
struct ChainPoint {
  P3 x{};
  size_t chain = 0;
  double s = 0;
};

/// Points along every chain of c at most `step` apart (and at every vertex), with the chains'
/// lengths.
std::vector<ChainPoint> samples(const CrackSurface &c, const std::vector<Chain> &chains,
                                double step, std::vector<double> &lengths) {
  std::vector<ChainPoint> out;
  const size_t m = c.points.size();
  lengths.assign(chains.size(), 0.0);
  for (size_t k = 0; k < chains.size(); ++k)
    for (const int e : chains[k].edges) {
      const P3 &p = c.points[static_cast<size_t>(e)],
               &q = c.points[(static_cast<size_t>(e) + 1) % m];
      const double len = dist(p, q);
      const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
      for (int i = 0; i <= n; ++i) {
        const double f = static_cast<double>(i) / n;
        out.push_back(
            {{p[0] + f * (q[0] - p[0]), p[1] + f * (q[1] - p[1]), p[2] + f * (q[2] - p[2])},
             k,
             lengths[k] + f * len});
      }
      lengths[k] += len;
    }
  return out;
}

/// The arc distance between two points of one chain (the shorter way round a closed one).
double arcBetween(double s0, double s1, double length, bool closed) {
  const double d = std::fabs(s1 - s0);
  return closed ? std::min(d, length - d) : d;
}

/// Where front point f lies on the chains: its chain and arc length (0, 0 when f's edge is on no
/// chain, which frontPoints never gives).
std::pair<size_t, double> onChain(const CrackSurface &c, const std::vector<Chain> &chains,
                                  const cracks::FrontPoint &f) {
  for (size_t k = 0; k < chains.size(); ++k) {
    double s = 0;
    for (const int e : chains[k].edges) {
      const P3 &p = c.points[static_cast<size_t>(e)];
      if (e == f.edge) return {k, s + dist(f.x, p)};
      s += dist(c.points[(static_cast<size_t>(e) + 1) % c.points.size()], p);
    }
  }
  return {0, 0.0};
}

/// A crack's front chains, their lengths and their points a quarter of the cell at the front
/// apart.
struct Fronts {
  std::vector<Chain> chains;
  std::vector<double> lengths;
  std::vector<ChainPoint> pts;
};

/// The clearance of front point f of crack k, over the samples of its chain within its tube's
/// half length L = R of it.
Clearance clearanceOf(const Scene<3> &sc, size_t k, const Fronts &fr, const cracks::FrontPoint &f,
                      double R, const std::vector<Surface> &surfaces,
                      const std::vector<char> &crossed) {
  const CrackSurface &c = sc.cracks[k];
  const std::vector<Chain> &chains = fr.chains;
  const std::vector<double> &lengths = fr.lengths;
  const std::vector<ChainPoint> &pts = fr.pts;
  const auto [chain, sf] = onChain(c, chains, f);
  const bool closed = chains[chain].closed;
  const double L = closed ? std::min(R, 0.5 * lengths[chain]) : R;
  std::vector<const ChainPoint *> piece;
  for (const ChainPoint &y : pts)
    if (y.chain == chain && arcBetween(y.s, sf, lengths[chain], closed) <= L) piece.push_back(&y);
  Clearance cl;
  for (const ChainPoint *y : piece) {
    for (size_t i = 0; i < surfaces.size(); ++i)
      if (!crossed[i]) cl.take(surfaces[i].distance(y->x), surfaces[i].name);
    for (size_t m = 0; m < sc.cracks.size(); ++m) {
      const double d = m == k ? INFINITY : cracks::distance(sc.cracks[m], y->x.data());
      if (d < cl.d) cl.take(d, "crack " + std::to_string(m));
    }
  }
  // Its own front elsewhere: a sample z of its front that the chain reaches only the long way
  // round from a piece sample y (closer than kBack times the arc between them, or on another
  // chain: the other side of a narrow crack, a penny crack's far side), whose neighbourhood the
  // nearest-point map of the tube gives to z: the tube ends at the bisector between them, half
  // their distance from y, where its weight would jump. A straight chain or one turning by a
  // right angle has distances of at least 0.707 times the arc. Every sample of the piece lies
  // within L of the point, so a z farther than L + 2 cl.d from it cannot come nearer.
  constexpr double kBack = 0.7;
  for (const ChainPoint &z : pts) {
    if (dist(z.x, f.x) - L >= 2 * cl.d) continue;
    for (const ChainPoint *y : piece) {
      const double d = dist(y->x, z.x);
      const bool back =
          z.chain != chain || d < kBack * arcBetween(y->s, z.s, lengths[chain], closed);
      if (back && 0.5 * d < cl.d)
        cl.take(0.5 * d, "its own crack's front at " + fmtList(z.x.data(), 3));
    }
  }
  return cl;
}

/// A given radius R larger than the body that holds a crack's front is refused rather than
/// clipped (a length in the wrong unit, say), as for a 2D tip.
void refuseLargerThanBody(const Scene<3> &sc, double R, double spacing) {
  for (size_t k = 0; k < sc.cracks.size(); ++k)
    for (const cracks::FrontPoint &f : cracks::frontPoints(sc.cracks[k], spacing)) {
      for (size_t i = 0; i < sc.bodies.size(); ++i) {
        const BoxOf<3> &b = sc.bodies[i].box;
        const double size =
            std::sqrt((b[3] - b[0]) * (b[3] - b[0]) + (b[4] - b[1]) * (b[4] - b[1]) +
                      (b[5] - b[2]) * (b[5] - b[2]));
        if (sc.bodies[i].inside(f.x.data()) && R > size)
          Options::bad("gimp_crack_j_radius", formatNumber(R),
                       "larger than body " + std::to_string(i) + " (" + formatNumber(size) +
                           " m across) at crack " + std::to_string(k) +
                           "; valid: at least 2 cells (" +
                           formatNumber(kJMinCells * frontCell(sc)) + " m), within the body");
      }
      break;
    }
}

void warn(const std::string &line) {
  PetscCallAbort(PETSC_COMM_WORLD,
                 PetscPrintf(PETSC_COMM_WORLD, "gimp: warning: %s\n", line.c_str()));
}

} // namespace

void setFrontDomains(Scene<3> &sc, bool radiusGiven, bool quiet) {
  sc.jDomain.clear();
  const double h = frontCell(sc);
  const double R = radiusGiven ? sc.crackJRadius : kJCells * h, lo = kJMinCells * h;
  const std::string opt = "gimp_crack_j_radius", val = formatNumber(R);
  if (radiusGiven && !quiet && !(R >= lo))
    Options::bad(opt, val,
                 "under 2 cells (cell " + formatNumber(h) + " m) at the front; valid: at least " +
                     formatNumber(lo) + " m");
  const double spacing = frontSpacing(sc);
  if (radiusGiven && !quiet) refuseLargerThanBody(sc, R, spacing);
  const std::vector<Surface> surfaces = surfacesOf(sc);
  for (size_t k = 0; k < sc.cracks.size(); ++k) {
    const CrackSurface &c = sc.cracks[k];
    Fronts fr;
    fr.chains = chainsOf(c);
    fr.pts = samples(c, fr.chains, 0.25 * h, fr.lengths);
    // The surfaces the front crosses: an end of one of its chains lies on them.
    std::vector<char> crossed(surfaces.size(), 0);
    for (const Chain &ch : fr.chains) {
      if (ch.closed) continue;
      const size_t m = c.points.size(), first = static_cast<size_t>(ch.edges.front());
      for (const P3 &end :
           {c.points[first], c.points[(static_cast<size_t>(ch.edges.back()) + 1) % m]})
        for (size_t i = 0; i < surfaces.size(); ++i)
          crossed[i] = crossed[i] || surfaces[i].distance(end) <= 1e-6 * h;
    }
    const std::vector<cracks::FrontPoint> fps = cracks::frontPoints(c, spacing);
    int clipped = 0, none = 0;
    Clearance nearest;
    P3 at{};
    for (const cracks::FrontPoint &f : fps) {
      const Clearance cl = clearanceOf(sc, k, fr, f, R, surfaces, crossed);
      const std::string point =
          "front point " + fmtList(f.x.data(), 3) + " of crack " + std::to_string(k);
      JDomain j{R, false};
      if (cl.d < lo) {
        if (radiusGiven && !quiet)
          Options::bad(opt, val,
                       "no tube fits at " + point + ": it is " + formatNumber(cl.d) + " m from " +
                           cl.what + ", less than 2 cells (" + formatNumber(lo) +
                           " m); without the option G and K are not measured there");
        j.radius = 0;
        ++none;
      } else if (R > cl.d) {
        j = {cl.d, true};
        ++clipped;
      }
      if (cl.d < nearest.d) {
        nearest = cl;
        at = f.x;
      }
      sc.jDomain.push_back(j);
    }
    if (quiet) continue;
    const std::string of =
        " of the " + std::to_string(fps.size()) + " front points of crack " + std::to_string(k);
    const std::string asked = radiusGiven ? "option -gimp_crack_j_radius " + val
                                          : "the default front radius " + val + " m (5 cells)";
    if (clipped)
      warn(asked + " reaches " + nearest.what + " at " + std::to_string(clipped) + of +
           " (the nearest " + fmtList(at.data(), 3) + ", " + formatNumber(nearest.d) +
           " m away): their tubes are clipped to their clearance (R of each front point in "
           "summary.json)");
    if (none)
      warn(std::to_string(none) + of + " are less than 2 cells (" + formatNumber(lo) + " m) from " +
           nearest.what +
           ": no tube fits there, G and K are not measured (null in "
           "summary.json)");
  }
}

} // namespace input

void updateFrontDomains(Scene<3> &sc) {
  input::setFrontDomains(sc, sc.crackJRadius > 0, true);
}

double frontCell(const Scene<3> &sc) {
  double h = sc.h;
  for (const CrackSurface &c : sc.cracks)
    for (const cracks::FrontPoint &f : cracks::frontPoints(c, sc.h))
      h = std::min(h, sc.cellSizeAt(f.x.data()));
  return h;
}

double frontSpacing(const Scene<3> &sc) {
  return sc.crackFrontSpacing > 0 ? sc.crackFrontSpacing : 2.0 * frontCell(sc);
}

} // namespace gimp
