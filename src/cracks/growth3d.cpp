// Crack growth along 3D fronts (-gimp_crack_growth mts; docs/method.md, *Crack growth*): the
// front points whose G reaches the toughness advance in the crack's plane, the polygon follows.
#include "front_chain.hpp"
#include "gimp/core/errors.hpp"
#include "gimp/cracks/growth.hpp"
#include "gimp/input/options.hpp"

#include <algorithm>
#include <cmath>

namespace gimp::cracks {

namespace {

using chain::cross;
using chain::dot;
using chain::norm;
using chain::P3;
using chain::sub;

P3 add(const P3 &a, const P3 &b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
P3 scaled(double s, const P3 &a) {
  return {s * a[0], s * a[1], s * a[2]};
}

/// Drops, one at a time and from the first vertex again after each, the vertices v of the
/// polygon (edge flags `front`, edge v leaving vertex v) that drop(p, v, a, b) names, p the
/// vertex before v, a and b the edges into and out of v; at least 3 vertices stay.
template <class Drop> void dropVertices(std::vector<P3> &pts, std::vector<char> &front, Drop drop) {
  bool changed = true;
  while (changed && pts.size() > 3) {
    changed = false;
    const size_t m = pts.size();
    for (size_t v = 0; v < m && !changed; ++v) {
      const size_t p = (v + m - 1) % m;
      if (!drop(p, v, sub(pts[v], pts[p]), sub(pts[(v + 1) % m], pts[v]))) continue;
      pts.erase(pts.begin() + static_cast<std::ptrdiff_t>(v));
      front.erase(front.begin() + static_cast<std::ptrdiff_t>(v));
      changed = true;
    }
  }
}

/// Drops the vertices between two mouth edges that continue each other in a straight line, and
/// vertices that repeat their predecessor (a carried mouth vertex landing on one already there).
void dropStraightMouths(std::vector<P3> &pts, std::vector<char> &front) {
  dropVertices(pts, front, [&](size_t p, size_t v, const P3 &a, const P3 &b) {
    const double la = norm(a), lb = norm(b);
    const bool repeat = la <= 1e-12 * lb;
    const bool straight =
        !front[p] && !front[v] && norm(cross(a, b)) <= 1e-9 * la * lb && dot(a, b) > 0;
    if (repeat) front[p] = front[v]; // the edge leaving v now leaves p
    return repeat || straight;
  });
}

/// Drops the front vertices (between two front edges) that leave an edge shorter than minLen or
/// turn the front back on itself (by more than 120 degrees), where neighbouring pieces that moved
/// by different amounts along different directions met: the front keeps its course without the
/// folds and slivers its measure would see as a crack near itself.
void dropFolds(std::vector<P3> &pts, std::vector<char> &front, double minLen) {
  dropVertices(pts, front, [&](size_t p, size_t v, const P3 &a, const P3 &b) {
    return front[p] && front[v] &&
           (norm(a) < minLen || norm(b) < minLen || dot(a, b) < -0.5 * norm(a) * norm(b));
  });
}

/// Puts each vertex where the front meets a mouth back on the bodies' surface: on the line of its
/// front edge, from the edge's other vertex (in the material) out to where that line leaves the
/// bodies, searched up to `reach` past the vertex (a vertex that moved along the mean of two
/// edges' directions may have left the surface it slid on by a little each increment).
void onSurface(const Scene<3> &sc, std::vector<P3> &pts, const std::vector<char> &front,
               double reach) {
  const auto inside = [&](const P3 &x) {
    for (const Body<3> &b : sc.bodies)
      if (b.inside(x.data())) return true;
    return false;
  };
  const size_t m = pts.size();
  for (size_t v = 0; v < m; ++v) {
    const char before = front[(v + m - 1) % m], after = front[v];
    if (before == after) continue;
    const P3 F = after ? pts[(v + 1) % m] : pts[(v + m - 1) % m];
    const P3 d = sub(pts[v], F);
    const double len = norm(d);
    if (!(len > 0) || !inside(F)) continue;
    const P3 u = scaled(1.0 / len, d);
    const double tMax = len + reach, dt = reach / 16;
    double lo = 0, hi = -1;
    for (double t = dt; t <= tMax + 0.5 * dt; t += dt) {
      if (!inside(add(F, scaled(std::min(t, tMax), u)))) {
        hi = std::min(t, tMax);
        break;
      }
      lo = std::min(t, tMax);
    }
    if (hi < 0) continue; // the line stays in the material: leave the vertex
    while (hi - lo > 1e-12 * tMax)
      (inside(add(F, scaled(0.5 * (lo + hi), u))) ? lo : hi) = 0.5 * (lo + hi);
    pts[v] = add(F, scaled(lo, u));
  }
}

std::string where(const double *x) {
  return input::fmtList(x, 3);
}

} // namespace

double twistAngle(double KI, double KIII, double nu) {
  if (KIII == 0) return 0.0;
  return 0.5 * std::atan2(2.0 * KIII, (1.0 - 2.0 * nu) * KI);
}

std::vector<P3> advanceFront(const CrackSurface &c, double spacing,
                             const std::vector<double> &advance, std::vector<char> *frontOut) {
  // The polygon with its front edges cut into their measuring pieces, each with its advance.
  std::vector<P3> V;
  std::vector<char> F;
  std::vector<double> S;
  const size_t m = c.points.size();
  size_t j = 0;
  for (size_t e = 0; e < m; ++e) {
    const P3 &p = c.points[e], &q = c.points[(e + 1) % m];
    if (!c.front[e]) {
      V.push_back(p);
      F.push_back(0);
      S.push_back(0);
      continue;
    }
    const int n = frontPieces(norm(sub(q, p)), spacing);
    for (int k = 0; k < n; ++k) {
      V.push_back(add(p, scaled(static_cast<double>(k) / n, sub(q, p))));
      F.push_back(1);
      S.push_back(advance.at(j++));
    }
  }
  CrackSurface cut = makeSurface(V, c.normal.data());
  cut.front = F;
  // Each vertex's move: along its ahead direction b, by s / (b . a) for the mean advance s of
  // its front pieces (a: a front piece's ahead direction; b . a is the same for both pieces).
  const size_t M = V.size();
  std::vector<P3> d(M, P3{0, 0, 0});
  std::vector<char> moved(M, 0);
  for (size_t v = 0; v < M; ++v) {
    const size_t ep = (v + M - 1) % M, en = v;
    if (!F[ep] && !F[en]) continue;
    const size_t f = F[ep] ? ep : en;
    const double s = F[ep] && F[en] ? 0.5 * (S[ep] + S[en]) : S[f];
    if (s == 0) continue;
    const P3 b = chain::vertexAhead(cut, v);
    double a[3], n[3], t[3];
    frontFrame(cut, static_cast<int>(f), a, n, t);
    d[v] = scaled(s / dot(b, P3{a[0], a[1], a[2]}), b);
    moved[v] = 1;
  }
  // The new polygon; a moved vertex where the front meets a mouth carries the mouth edge's far
  // vertex along (inserted next to it), so the crack still reaches as far past the surface.
  std::vector<P3> out;
  std::vector<char> flags;
  for (size_t v = 0; v < M; ++v) {
    const size_t ep = (v + M - 1) % M, en = v;
    if (moved[v] && !F[ep] && F[en]) {
      out.push_back(add(V[ep], d[v]));
      flags.push_back(0);
    }
    out.push_back(add(V[v], d[v]));
    flags.push_back(F[en]);
    if (moved[v] && F[ep] && !F[en]) {
      out.push_back(add(V[(v + 1) % M], d[v]));
      flags.push_back(0);
    }
  }
  dropStraightMouths(out, flags);
  dropFolds(out, flags, 0.25 * *std::max_element(advance.begin(), advance.end()));
  if (frontOut) *frontOut = flags;
  return out;
}

CrackSurface growthReach(const CrackSurface &c, double length) {
  // In the plane's (e1, e2) coordinates: the polygon's vertices and, around each front vertex, a
  // circle of radius 1.25 length (a 16-gon about it, circumscribed): a vertex where the front
  // meets a mouth moves up to 1 / cos(22.5 degrees) = 1.08 times as far as the front
  // (advanceFront); their convex hull.
  std::vector<std::array<double, 2>> pts(c.uv.begin(), c.uv.end());
  const size_t m = c.points.size();
  const int sides = 16;
  const double r = 1.25 * length / std::cos(M_PI / sides);
  for (size_t v = 0; v < m; ++v) {
    if (!c.front[v] && !c.front[(v + m - 1) % m]) continue;
    for (int k = 0; k < sides; ++k)
      pts.push_back({c.uv[v][0] + r * std::cos(2 * M_PI * k / sides),
                     c.uv[v][1] + r * std::sin(2 * M_PI * k / sides)});
  }
  std::sort(pts.begin(), pts.end());
  const auto turn = [](const std::array<double, 2> &o, const std::array<double, 2> &a,
                       const std::array<double, 2> &b) {
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
  };
  std::vector<std::array<double, 2>> hull(2 * pts.size());
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i) { // lower hull, then upper (counter-clockwise)
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], pts[i]) <= 0)
      --k;
    hull[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && turn(hull[k - 2], hull[k - 1], pts[i]) <= 0)
      --k;
    hull[k++] = pts[i];
  }
  hull.resize(k - 1);
  std::vector<P3> out;
  for (const auto &q : hull)
    out.push_back(add(c.origin, add(scaled(q[0], c.e1), scaled(q[1], c.e2))));
  CrackSurface reach = makeSurface(out, c.normal.data());
  reach.front.assign(reach.points.size(), 0);
  return reach;
}

std::vector<Release<3>> releasing(const Scene<3> &sc, double t) {
  std::vector<Release<3>> out;
  if (!(sc.growthRelease > 0)) return out;
  for (const FrontGrowth &g : sc.frontGrowth)
    for (const auto &[t0, before] : g.opening)
      if (t - t0 < sc.growthRelease) out.push_back({g.crack, before, t0});
  return out;
}

std::vector<GrowthRecord> growFronts(Scene<3> &sc, const std::vector<FrontMeasure> &front, double t,
                                     std::vector<std::string> &stops) {
  std::vector<GrowthRecord> out;
  const double spacing = frontSpacing(sc);
  for (FrontGrowth &g : sc.frontGrowth) {
    if (g.stopped) continue;
    CrackSurface &c = sc.cracks[static_cast<size_t>(g.crack)];
    const std::vector<FrontPoint> pts = frontPoints(c, spacing);
    std::vector<const FrontMeasure *> ms;
    for (const FrontMeasure &f : front)
      if (f.crack == g.crack) ms.push_back(&f);
    const std::string crack = "crack " + std::to_string(g.crack);
    const auto stop = [&](const std::string &why) {
      g.stopped = true;
      stops.push_back(crack + " stops growing at t " + formatNumber(t) + " s: " + why);
    };
    if (ms.size() != pts.size()) { // the measures were taken on this polygon: never
      stop("its front changed between the measure and the growth check");
      continue;
    }
    std::vector<double> advance(pts.size(), 0.0);
    std::vector<double> kink(pts.size(), 0.0);
    std::string why;
    for (size_t j = 0; j < pts.size() && why.empty(); ++j) {
      const FrontMeasure &f = *ms[j];
      if (!(f.R > 0)) {
        why = "no tube fits at front point " + where(f.x.data()) +
              " (it is closer than 2 cells to a surface or crack), so G is not measured there";
        break;
      }
      const Material &mat = sc.materialAt(f.x.data());
      if (!(mat.Gc > 0 && f.G >= mat.Gc)) continue;
      const double theta = mtsKink(f.KI, f.KII), psi = twistAngle(f.KI, f.KIII, mat.nu);
      if (std::fabs(theta) > kPlanarGrowthAngle)
        why = "front point " + where(f.x.data()) + " would kink by " +
              formatNumber(theta * 180 / M_PI) +
              " degrees (K_II / K_I = " + formatNumber(f.KII / f.KI) +
              "): 3D cracks grow in their plane, within " +
              formatNumber(kPlanarGrowthAngle * 180 / M_PI) + " degrees";
      else if (std::fabs(psi) > kPlanarGrowthAngle)
        why = "front point " + where(f.x.data()) + " would twist by " +
              formatNumber(psi * 180 / M_PI) +
              " degrees (K_III / K_I = " + formatNumber(f.KIII / f.KI) +
              "): 3D cracks grow in their plane, within " +
              formatNumber(kPlanarGrowthAngle * 180 / M_PI) + " degrees";
      advance[j] = g.step;
      kink[j] = theta;
    }
    if (!why.empty()) {
      stop(why);
      continue;
    }
    if (std::all_of(advance.begin(), advance.end(), [](double s) { return s == 0; })) continue;
    std::vector<char> flags;
    std::vector<P3> grown = advanceFront(c, spacing, advance, &flags);
    onSurface(sc, grown, flags, g.step);
    const double h = sc.cellSizeAt(pts.front().x.data());
    if (findFault(grown, 1e-9 * h).kind != SurfaceFault::None) {
      stop("the next increment would make its polygon cross itself");
      continue;
    }
    // Each front point stays within the growth length of the crack as given, and the polygon
    // within the region whose nodes got second fields (growthReach: a vertex between two pieces
    // moves a little farther than they do).
    const CrackSurface reach = growthReach(g.start, g.length);
    for (size_t j = 0; j < pts.size() && why.empty(); ++j) {
      P3 x{};
      for (int a = 0; a < 3; ++a)
        x[a] = pts[j].x[a] + advance[j] * pts[j].a[a];
      if (distance(g.start, x.data()) > g.length * (1 + 1e-9))
        why = "the next increment would take front point " + where(pts[j].x.data()) + " to " +
              where(x.data()) + ", past its growth length " + formatNumber(g.length) +
              " m (-gimp_crack_growth_length) from the crack as given";
    }
    if (!why.empty()) {
      stop(why);
      continue;
    }
    const CrackSurface next = classifyCrackEdges(sc, makeSurface(grown, c.normal.data()));
    const size_t nv = next.points.size();
    for (size_t v = 0; v < nv && why.empty(); ++v)
      if ((next.front[v] || next.front[(v + nv - 1) % nv]) &&
          distance(reach, next.points[v].data()) > 1e-9 * h)
        why = "the next increment would take its front to " + where(next.points[v].data()) +
              ", past the reach of its growth length " + formatNumber(g.length) +
              " m (-gimp_crack_growth_length) from the crack as given";
    if (!why.empty()) {
      stop(why);
      continue;
    }
    if (std::none_of(next.front.begin(), next.front.end(), [](char f) { return f != 0; })) {
      stop("the next increment would leave no front in the material (it would cut its body)");
      continue;
    }
    for (size_t k = 0; k < sc.cracks.size() && why.empty(); ++k) {
      double at[3];
      if (static_cast<int>(k) != g.crack && surfacesMeet(next, sc.cracks[k], at))
        why = "the next increment would meet crack " + std::to_string(k) + " at " + where(at);
    }
    if (!why.empty()) {
      stop(why);
      continue;
    }
    if (sc.growthRelease > 0) { // the polygon before it, while the advance opens
      auto &o = g.opening;
      o.erase(std::remove_if(o.begin(), o.end(),
                             [&](const auto &b) { return !(t - b.first < sc.growthRelease); }),
              o.end());
      o.emplace_back(t, c);
    }
    c = next;
    for (size_t j = 0; j < pts.size(); ++j) {
      if (advance[j] == 0) continue;
      const FrontMeasure &f = *ms[j];
      GrowthRecord r;
      r.t = t;
      r.crack = g.crack;
      r.end = static_cast<int>(j);
      for (int a = 0; a < 3; ++a)
        r.x[a] = pts[j].x[a] + advance[j] * pts[j].a[a];
      r.G = f.G;
      r.KI = f.KI;
      r.KII = f.KII;
      r.KIII = f.KIII;
      r.kink = kink[j] * 180.0 / M_PI;
      out.push_back(r);
    }
  }
  return out;
}

} // namespace gimp::cracks
