// Reading the cracks of a 3D scene (-gimp_cracks, -gimp_crackK_polygon or -gimp_crackK_disk):
// each polygon checked against itself, the bodies and the other cracks; each edge classified as
// a front (inside the material) or a mouth (on or outside a body's surface).
#include "scene_options.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gimp::input {

namespace {

using P3 = std::array<double, 3>;

/// Strictly inside a body: x and the six points tol away from it along the axes are inside.
bool strictlyInsideABody(const Scene<3> &sc, const double *x) {
  const double tol = 1e-9 * sc.cellSizeAt(x);
  for (const Body<3> &b : sc.bodies) {
    bool in = b.inside(x);
    for (int q = 0; q < 6 && in; ++q) {
      double y[3] = {x[0], x[1], x[2]};
      y[q / 2] += q % 2 ? tol : -tol;
      in = b.inside(y);
    }
    if (in) return true;
  }
  return false;
}

/// Where the edge p-q (sampled at a quarter of the finest cell, at most 1e4 samples, its ends
/// excluded) passes between strictly inside a body and not: each change located by bisection to
/// 1e-12 of the edge, as parameters in (0, 1), in order.
std::vector<double> surfaceCrossings(const Scene<3> &sc, const P3 &p, const P3 &q) {
  const auto at = [&](double s) {
    const double x[3] = {p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1]),
                         p[2] + s * (q[2] - p[2])};
    return strictlyInsideABody(sc, x);
  };
  const double len = std::sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                               (q[2] - p[2]) * (q[2] - p[2]));
  const double hmin = sc.finestCell();
  const int n = static_cast<int>(std::clamp(std::ceil(len / (0.25 * hmin)), 2.0, 1e4));
  std::vector<double> out;
  double s0 = 0.5 / n;
  bool in0 = at(s0);
  for (int i = 1; i < n; ++i) {
    const double s1 = (i + 0.5) / n;
    const bool in1 = at(s1);
    if (in1 != in0) {
      double lo = s0, hi = s1;
      while (hi - lo > 1e-12)
        (at(0.5 * (lo + hi)) == in0 ? lo : hi) = 0.5 * (lo + hi);
      out.push_back(0.5 * (lo + hi));
    }
    s0 = s1;
    in0 = in1;
  }
  return out;
}

/// The polygon with its edges cut where they pass through a body's surface, each piece a front
/// (its middle strictly inside a body) or a mouth.
CrackSurface classifyEdges(const Scene<3> &sc, const CrackSurface &c0) {
  std::vector<P3> pts;
  std::vector<char> front;
  const size_t m = c0.points.size();
  for (size_t e = 0; e < m; ++e) {
    const P3 &p = c0.points[e], &q = c0.points[(e + 1) % m];
    std::vector<double> cuts = surfaceCrossings(sc, p, q);
    cuts.insert(cuts.begin(), 0.0);
    cuts.push_back(1.0);
    for (size_t k = 0; k + 1 < cuts.size(); ++k) {
      const double s = cuts[k], mid = 0.5 * (cuts[k] + cuts[k + 1]);
      pts.push_back({p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1]), p[2] + s * (q[2] - p[2])});
      const double x[3] = {p[0] + mid * (q[0] - p[0]), p[1] + mid * (q[1] - p[1]),
                           p[2] + mid * (q[2] - p[2])};
      front.push_back(static_cast<char>(strictlyInsideABody(sc, x)));
    }
  }
  CrackSurface c = cracks::makeSurface(pts, c0.normal.data());
  c.front = front; // makeSurface keeps the order: the normal is the same
  return c;
}

/// The vertices of -gimp_crackK_disk c, n, r: a regular polygon inscribed in the circle, its
/// edges about one cell at the circle's finest level (at least 32, a multiple of 4).
std::vector<P3> diskPolygon(const Scene<3> &sc, const std::string &q,
                            const std::vector<double> &v) {
  const std::string all = fmtList(v.data(), v.size());
  if (v.size() != 7) Options::bad(q, all, "needs cx,cy,cz,nx,ny,nz,r: centre, normal, radius [m]");
  const double nl = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5]);
  if (!(nl > 0)) Options::bad(q, all, "the normal nx,ny,nz must not be zero");
  if (!(v[6] > 0)) Options::bad(q, all, "the radius must be > 0 [m]");
  const P3 n = {v[3] / nl, v[4] / nl, v[5] / nl};
  // e1: the axis least aligned with n, made orthogonal to it; e2 = n x e1.
  const int least = std::fabs(n[0]) <= std::fabs(n[1]) && std::fabs(n[0]) <= std::fabs(n[2]) ? 0
                    : std::fabs(n[1]) <= std::fabs(n[2])                                     ? 1
                                                                                             : 2;
  P3 e1{0, 0, 0};
  e1[least] = 1;
  const double en = e1[0] * n[0] + e1[1] * n[1] + e1[2] * n[2];
  for (int a = 0; a < 3; ++a)
    e1[a] -= en * n[a];
  const double el = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
  for (double &c : e1)
    c /= el;
  const P3 e2 = {n[1] * e1[2] - n[2] * e1[1], n[2] * e1[0] - n[0] * e1[2],
                 n[0] * e1[1] - n[1] * e1[0]};
  double hmin = sc.h;
  for (int k = 0; k < 64; ++k) { // the finest cell on the circle
    const double t = 2 * M_PI * k / 64;
    const double x[3] = {v[0] + v[6] * (std::cos(t) * e1[0] + std::sin(t) * e2[0]),
                         v[1] + v[6] * (std::cos(t) * e1[1] + std::sin(t) * e2[1]),
                         v[2] + v[6] * (std::cos(t) * e1[2] + std::sin(t) * e2[2])};
    hmin = std::min(hmin, sc.cellSizeAt(x));
  }
  const int sides = 4 * std::max(8, static_cast<int>(std::ceil(2 * M_PI * v[6] / hmin / 4)));
  std::vector<P3> out;
  for (int k = 0; k < sides; ++k) {
    const double t = 2 * M_PI * k / sides;
    out.push_back({v[0] + v[6] * (std::cos(t) * e1[0] + std::sin(t) * e2[0]),
                   v[1] + v[6] * (std::cos(t) * e1[1] + std::sin(t) * e2[1]),
                   v[2] + v[6] * (std::cos(t) * e1[2] + std::sin(t) * e2[2])});
  }
  return out;
}

/// The crack of option q: the polygon checked, its edges classified.
CrackSurface makeCrack(const Scene<3> &sc, const std::string &q, std::vector<P3> pts,
                       const std::string &all) {
  const double tol = 1e-9 * sc.h;
  const cracks::SurfaceFault f = cracks::findFault(pts, tol);
  const std::string i = std::to_string(f.i), j = std::to_string(f.j);
  if (f.kind == cracks::SurfaceFault::Degenerate)
    Options::bad(q, all, "needs at least 3 points x,y,z that span an area [m]");
  if (f.kind == cracks::SurfaceFault::ZeroLength)
    Options::bad(q, all, "edge " + i + " has zero length: points must differ");
  if (f.kind == cracks::SurfaceFault::NotPlanar)
    Options::bad(q, all, "point " + i + " is off the plane of the others: a crack is planar");
  if (f.kind == cracks::SurfaceFault::Intersects)
    Options::bad(q, all,
                 "edges " + i + " and " + j + " meet: a crack polygon may not cross itself");
  const CrackSurface c = classifyEdges(sc, cracks::makeSurface(pts));
  if (std::none_of(c.front.begin(), c.front.end(), [](char x) { return x != 0; }))
    Options::bad(q, all, "no edge lies inside a body: a crack needs a front in the material");
  return c;
}

/// Crack growth along the fronts (-gimp_crack_growth mts): each crack's increment (one cell at
/// its front unless given) and the farthest its front may advance, and the refusals of what would
/// not grow as asked. After the front domains are set.
void readGrowth(const Options &o, Scene<3> &sc, PetscInt nc) {
  const GrowthAsked asked = readGrowthOptions(o, sc, sc.bodies.size(), nc);
  if (!asked.grows) return;
  const double spacing = frontSpacing(sc);
  bool anyTough = false;
  size_t q = 0; // the front point's index in sc.jDomain
  for (size_t k = 0; k < sc.cracks.size(); ++k) {
    FrontGrowth g;
    g.crack = static_cast<int>(k);
    g.start = sc.cracks[k];
    double h = sc.h;
    for (const cracks::FrontPoint &f : cracks::frontPoints(sc.cracks[k], spacing)) {
      h = std::min(h, sc.cellSizeAt(f.x.data()));
      anyTough = anyTough || sc.materialAt(f.x.data()).Gc > 0;
    }
    g.step = asked.stepGiven ? asked.step : h;
    g.length = asked.lengthGiven ? asked.length : 20.0 * g.step;
    for (const cracks::FrontPoint &f : cracks::frontPoints(sc.cracks[k], spacing)) {
      const double R = sc.jDomain[q++].radius;
      refuseGrowthAt({"front point " + fmtList(f.x.data(), 3) + " of crack " + std::to_string(k),
                      "tube", "front radius", "a surface or crack", "G at every front point"},
                     R, g.step);
    }
    if (g.length < g.step)
      Options::bad("gimp_crack_growth_length", formatNumber(g.length),
                   "shorter than the growth step " + formatNumber(g.step) + " m of crack " +
                       std::to_string(k) + ": valid from one growth step");
    sc.frontGrowth.push_back(g);
  }
  if (!anyTough)
    Options::bad("gimp_crack_growth", "mts",
                 "needs a toughness: -gimp_Gc [J/m^2] (or -gimp_bodyK_Gc for the bodies that hold "
                 "the fronts)");
}

} // namespace

void readCracks(const Options &o, Scene<3> &sc) {
  const PetscInt nc = o.integer("gimp_cracks", 0);
  bool radiusGiven = false;
  sc.crackJRadius = o.real("gimp_crack_j_radius", sc.crackJRadius, &radiusGiven);
  sc.crackFrontSpacing = o.real("gimp_crack_front_spacing", 0.0);
  o.needs(nc > 0, "gimp_crack_j_radius", "cracks (-gimp_cracks)");
  o.needs(nc > 0, "gimp_crack_front_spacing", "cracks (-gimp_cracks)");
  for (PetscInt k = 0; k < (o.help() ? 1 : nc); ++k) {
    const std::string p = "gimp_crack" + std::to_string(k) + "_polygon",
                      d = "gimp_crack" + std::to_string(k) + "_disk";
    const bool polygon = o.given(p), disk = o.given(d);
    if (o.help()) {
      (void)o.reals(p);
      (void)o.reals(d);
      continue;
    }
    if (!polygon && !disk)
      Options::bad(p, "(missing)",
                   "give each crack a polygon (-" + p + " x,y,z,...) or a disk (-" + d +
                       " cx,cy,cz,nx,ny,nz,r) [m]");
    const std::vector<double> v = o.reals(disk ? d : p, true);
    if (polygon && disk)
      Options::bad(d, fmtList(v.data(), v.size()), "give -" + p + " or -" + d + ", not both");
    const std::string q = disk ? d : p, all = fmtList(v.data(), v.size());
    std::vector<P3> pts;
    if (disk) {
      pts = diskPolygon(sc, q, v);
    } else {
      if (v.size() % 3 || v.size() < 9)
        Options::bad(q, all, "needs triples x,y,z of at least 3 points [m]");
      if (v.size() > 3000)
        Options::bad(q, "(more than 1000 points)", "at most 1000 points (3000 values) [m]");
      for (size_t i = 0; i < v.size(); i += 3)
        pts.push_back({v[i], v[i + 1], v[i + 2]});
    }
    sc.cracks.push_back(makeCrack(sc, q, pts, all));
    for (size_t m = 0; m + 1 < sc.cracks.size(); ++m) {
      double at[3];
      if (cracks::surfacesMeet(sc.cracks.back(), sc.cracks[m], at))
        Options::bad(q, all,
                     "meets crack " + std::to_string(m) + " at " + fmtList(at, 3) +
                         ": cracks must not cross or touch");
    }
  }
  setFrontDomains(sc, radiusGiven);
  readGrowth(o, sc, nc);
}

} // namespace gimp::input

namespace gimp {

CrackSurface classifyCrackEdges(const Scene<3> &sc, const CrackSurface &c) {
  return input::classifyEdges(sc, c);
}

} // namespace gimp
