// Reading the cracks of a scene (-gimp_cracks, -gimp_crackK_points): each polyline checked
// against itself, the bodies and the other cracks; each end classified as a tip or a mouth; and
// their growth (-gimp_crack_growth and its options).
#include "scene_options.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gimp::input {

namespace {

/// The finest cell size among the levels whose box contains (x, y) (sc.h outside the grid).
double cellSizeAt(const Scene<2> &sc, double x, double y) {
  const double p[2] = {x, y};
  return sc.cellSizeAt(p);
}

/// In the body and farther than tol from its edge (the box's sides and the holes' circles).
bool strictlyInside(const Body<2> &b, double x, double y, double tol) {
  if (!b.inside(x, y) || x - b.box[0] <= tol || b.box[2] - x <= tol || y - b.box[1] <= tol ||
      b.box[3] - y <= tol)
    return false;
  for (const Hole &c : b.holes)
    if (std::hypot(x - c.cx, y - c.cy) <= c.r + tol) return false;
  return true;
}

bool strictlyInsideABody(const Scene<2> &sc, double x, double y) {
  const double tol = 1e-9 * cellSizeAt(sc, x, y);
  for (const Body<2> &b : sc.bodies)
    if (strictlyInside(b, x, y, tol)) return true;
  return false;
}

/// Whether some point of the polyline lies strictly inside a body: each segment sampled at a
/// quarter of the finest cell size (at most 1e5 samples per segment).
bool reachesABody(const Scene<2> &sc, const Crack &c, double hmin) {
  for (size_t k = 0; k + 1 < c.points.size(); ++k) {
    const auto &p = c.points[k], &r = c.points[k + 1];
    const double n = std::ceil(std::min(1e5, std::hypot(r[0] - p[0], r[1] - p[1]) / (0.25 * hmin)));
    for (double i = 0; i <= n; ++i)
      if (strictlyInsideABody(sc, p[0] + i / n * (r[0] - p[0]), p[1] + i / n * (r[1] - p[1])))
        return true;
  }
  return false;
}

/// The crack of option q from its n values: the polyline checked, its ends classified.
void makeCrack(const Scene<2> &sc, const std::string &q, const std::vector<double> &v, Crack &c) {
  const size_t n = v.size();
  const std::string all = fmtList(v.data(), n);
  if (n < 4) Options::bad(q, all, "needs pairs x,y of at least two points [m]");
  for (size_t i = 0; i < n; i += 2)
    c.points.push_back({v[i], v[i + 1]});
  const double hmin = sc.finestCell();
  const cracks::PolylineFault f = cracks::findFault(c, 1e-9 * hmin);
  const std::string i = std::to_string(f.i), j = std::to_string(f.j);
  if (f.kind == cracks::PolylineFault::ZeroLength)
    Options::bad(q, all, "points " + i + " and " + j + " coincide: segments must have a length");
  if (f.kind == cracks::PolylineFault::FoldsBack)
    Options::bad(q, all,
                 "segments " + i + " and " + j +
                     " fold back onto each other: a crack may not retrace itself");
  if (f.kind == cracks::PolylineFault::Intersects)
    Options::bad(q, all,
                 "segments " + i + " and " + j + " intersect: a crack may not cross itself");
  if (!reachesABody(sc, c, hmin))
    Options::bad(
        q, all,
        "no point of the crack lies inside a body (in its box, not on an edge or in a hole): a "
        "crack must run into a body");
  for (int e = 0; e < 2; ++e) {
    const auto &x = e ? c.points.back() : c.points.front();
    c.tip[e] = strictlyInsideABody(sc, x[0], x[1]);
  }
}

/// The points of crack k as its option gives them.
std::string pointsText(const Crack &c) {
  std::vector<double> v;
  for (const auto &p : c.points)
    v.insert(v.end(), p.begin(), p.end());
  return fmtList(v.data(), v.size());
}

/// Crack k crossing or touching an earlier crack (a tip on another crack, a T, an X).
void checkMeetings(const Scene<2> &sc, size_t k) {
  for (size_t m = 0; m < k; ++m) {
    double at[2];
    const int meet = cracks::cracksMeet(sc.cracks[k], sc.cracks[m], at);
    if (!meet) continue;
    const std::string other = "gimp_crack" + std::to_string(m) + "_points";
    Options::bad("gimp_crack" + std::to_string(k) + "_points", pointsText(sc.cracks[k]),
                 std::string(meet == 2 ? "crosses" : "touches") + " -" + other + " at " +
                     formatNumber(at[0]) + "," + formatNumber(at[1]) +
                     ": cracks must not cross or touch");
  }
}

/// Calls visit(k, e, x, h) for every crack tip in order (crack k, then end e), x the tip and h
/// the finest cell there.
template <class Visit> void forEachTip(const Scene<2> &sc, Visit &&visit) {
  for (size_t k = 0; k < sc.cracks.size(); ++k)
    for (int e = 0; e < 2; ++e) {
      const Crack &c = sc.cracks[k];
      if (!c.tip[e]) continue;
      const auto &x = e ? c.points.back() : c.points.front();
      visit(k, e, x, cellSizeAt(sc, x[0], x[1]));
    }
}

/// A tip closer than one cell (the finest cell at the tip) to another crack.
void checkTips(const Scene<2> &sc) {
  forEachTip(sc, [&](size_t k, int, const std::array<double, 2> &x, double h) {
    const Crack &c = sc.cracks[k];
    for (size_t m = 0; m < sc.cracks.size(); ++m) {
      const double d = cracks::distance(sc.cracks[m], x[0], x[1]);
      if (m == k || d >= h) continue;
      Options::bad("gimp_crack" + std::to_string(k) + "_points", pointsText(c),
                   "its tip " + formatNumber(x[0]) + "," + formatNumber(x[1]) + " is " +
                       formatNumber(d) + " m from crack " + std::to_string(m) +
                       ", less than one cell (" + formatNumber(h) +
                       " m): a tip must be at least one cell from another crack");
    }
  });
}

/// Crack growth (-gimp_crack_growth mts): each tip's increment and the longest it may grow, and
/// the refusals of what would not grow as asked. After the J domains are set.
void readGrowth(const Options &o, Scene<2> &sc, PetscInt nc) {
  const GrowthAsked asked = readGrowthOptions(o, sc, sc.bodies.size(), nc);
  if (!asked.grows) return;
  const double step = asked.step, length = asked.length;
  const bool stepGiven = asked.stepGiven, lengthGiven = asked.lengthGiven;
  bool anyTough = false;
  forEachTip(sc, [&](size_t k, int e, const std::array<double, 2> &x, double h) {
    anyTough = anyTough || sc.materialAt(x.data()).Gc > 0;
    TipGrowth g;
    g.crack = static_cast<int>(k);
    g.end = e;
    g.origin = x;
    g.step = stepGiven ? step : h;
    g.length = lengthGiven ? length : 20.0 * g.step;
    const double R = sc.jDomain[sc.tipGrowth.size()].radius;
    const std::string tip = "the tip " + formatNumber(x[0]) + "," + formatNumber(x[1]) +
                            " of crack " + std::to_string(k);
    refuseGrowthAt({tip, "J domain", "J radius", "an edge or crack", "G by J at every tip"}, R,
                   g.step);
    if (g.length < g.step)
      Options::bad("gimp_crack_growth_length", formatNumber(g.length),
                   "shorter than the growth step " + formatNumber(g.step) + " m at " + tip +
                       ": valid from one growth step");
    sc.tipGrowth.push_back(g);
  });
  if (sc.tipGrowth.empty())
    Options::bad("gimp_crack_growth", "mts",
                 "no crack has a tip (an end strictly inside a body): nothing can grow");
  if (!anyTough)
    Options::bad("gimp_crack_growth", "mts",
                 "needs a toughness: -gimp_Gc [J/m^2] (or -gimp_bodyK_Gc for the bodies that hold "
                 "the tips)");
}

} // namespace

void refuseGrowthAt(const GrowthPlace &p, double R, double step) {
  if (R <= 0)
    Options::bad("gimp_crack_growth", "mts",
                 std::string("no ") + p.domain + " fits at " + p.at +
                     " (it is closer than 2 cells to " + p.near + "): growth needs " + p.needs +
                     "; use -gimp_crack_growth none");
  if (step > R)
    Options::bad("gimp_crack_growth_step", formatNumber(step),
                 std::string("larger than the ") + p.radius + " " + formatNumber(R) + " m at " +
                     p.at + ": valid up to the " + p.radius);
}

GrowthAsked readGrowthOptions(const Options &o, Measures &m, size_t bodies, PetscInt nc) {
  GrowthAsked a;
  m.growth = o.choice("gimp_crack_growth", "none") == "mts" ? Growth::Mts : Growth::None;
  a.step = o.real("gimp_crack_growth_step", 0, &a.stepGiven);
  a.length = o.real("gimp_crack_growth_length", 0, &a.lengthGiven);
  m.growthInterval = static_cast<int>(o.integer("gimp_crack_growth_interval", m.growthInterval));
  m.growthRelease = o.real("gimp_crack_growth_release", m.growthRelease);
  if (o.help()) return a;
  a.grows = m.growth == Growth::Mts;
  o.needs(nc > 0, "gimp_crack_growth", "cracks (-gimp_cracks)");
  for (const char *q : {"gimp_crack_growth_step", "gimp_crack_growth_length",
                        "gimp_crack_growth_interval", "gimp_crack_growth_release"})
    o.needs(a.grows, q, "-gimp_crack_growth mts");
  // A toughness without growth would do nothing: refused.
  std::vector<std::string> tough;
  if (o.given("gimp_Gc")) tough.push_back("gimp_Gc");
  for (size_t b = 0; b < bodies; ++b)
    if (o.given("gimp_body" + std::to_string(b) + "_Gc"))
      tough.push_back("gimp_body" + std::to_string(b) + "_Gc");
  for (const std::string &q : tough)
    o.needs(a.grows, q, "-gimp_crack_growth mts (a toughness alone grows no crack)");
  return a;
}

void readCracks(const Options &o, Scene<2> &sc) {
  const PetscInt nc = o.integer("gimp_cracks", 0);
  bool radiusGiven = false;
  sc.crackJRadius = o.real("gimp_crack_j_radius", sc.crackJRadius, &radiusGiven);
  o.needs(nc > 0, "gimp_crack_j_radius", "cracks (-gimp_cracks)");
  for (PetscInt k = 0; k < (o.help() ? 1 : nc); ++k) {
    const std::string q = "gimp_crack" + std::to_string(k) + "_points";
    const std::vector<double> v = o.reals(q, !o.help());
    if (o.help()) continue;
    if (v.size() > 200)
      Options::bad(q, "(more than 100 points)", "at most 100 points (200 values) [m]");
    Crack c;
    makeCrack(sc, q, v, c);
    sc.cracks.push_back(c);
    checkMeetings(sc, sc.cracks.size() - 1);
  }
  if (o.help()) return readGrowth(o, sc, nc);
  checkTips(sc);
  setJDomains(sc, radiusGiven);
  readGrowth(o, sc, nc);
}

} // namespace gimp::input
