#include "gimp/cracks/growth.hpp"

#include "gimp/geometry/crack.hpp"

#include <cmath>
#include <cstdio>

namespace gimp::cracks {

double mtsKink(double KI, double KII) {
  if (KII == 0) return 0.0;
  const double S = std::sqrt(KI * KI + 8.0 * KII * KII);
  if (KI >= 0) return 2.0 * std::atan(-2.0 * KII / (KI + S));
  return 2.0 * std::atan((KI - S) / (4.0 * KII));
}

namespace {

/// K_II at or below this fraction of |K_I| is the round-off of the interaction integrals' sums
/// (a mode-I tip reads about 1e-11 of K_I): the tip grows straight on. The kink it would give,
/// below 2e-8 rad, moves the new tip less than 2e-8 of the increment; applied, such kinks drift a
/// tip on a line of nodes off it by round-off, until the two faces no longer meet those nodes
/// alike and the tip's fields lose their symmetry (docs/method.md, *Crack growth*).
constexpr double kModeIIRoundoff = 1e-8;

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

/// Why the tip of crack k at end e may not move to x, or "".
std::string refusal(const Scene<2> &sc, const TipGrowth &g, const std::array<double, 2> &from,
                    const std::array<double, 2> &x) {
  const Crack &c = sc.cracks[static_cast<size_t>(g.crack)];
  const int done = c.grown[g.end];
  if ((done + 1) * g.step > g.length * (1 + 1e-12))
    return "it has grown its growth length " + fmt(g.length) + " m (-gimp_crack_growth_length)";
  bool inBody = false;
  for (const Body<2> &b : sc.bodies)
    inBody = inBody || (b.inside(from[0], from[1]) && b.inside(x[0], x[1]));
  if (!inBody) return "the next increment would leave its body";
  const double h = sc.cellSizeAt(x.data());
  for (size_t m = 0; m < sc.cracks.size(); ++m) {
    if (static_cast<int>(m) == g.crack) continue;
    const Crack &o = sc.cracks[m];
    for (size_t s = 0; s + 1 < o.points.size(); ++s)
      if (segmentDistance(from, x, o.points[s], o.points[s + 1]) < h)
        return "the next increment would come within a cell of crack " + std::to_string(m);
  }
  Crack longer = c;
  if (g.end == 0)
    longer.points.insert(longer.points.begin(), x);
  else
    longer.points.push_back(x);
  if (findFault(longer, 1e-9 * h).kind != PolylineFault::None)
    return "the next increment would cross or retrace its own crack";
  return "";
}

} // namespace

std::vector<Release<2>> releasing(const Scene<2> &sc, const std::vector<GrowthRecord> &grown,
                                  double t) {
  std::vector<Release<2>> out;
  if (!(sc.growthRelease > 0)) return out;
  for (const GrowthRecord &r : grown) {
    if (!(t - r.t < sc.growthRelease)) continue;
    const auto &pts = sc.cracks[static_cast<size_t>(r.crack)].points;
    for (size_t i = 0; i < pts.size(); ++i) {
      if (pts[i][0] != r.x[0] || pts[i][1] != r.x[1]) continue;
      const size_t before = r.end == 0 ? i + 1 : i - 1; // (i > 0 at end 1: a crack has 2 points)
      if (before < pts.size()) out.push_back({pts[before], pts[i], r.t});
      break;
    }
  }
  return out;
}

std::vector<GrowthRecord> growTips(Scene<2> &sc, const std::vector<TipMeasure> &tips, double t,
                                   std::vector<std::string> &stops) {
  std::vector<GrowthRecord> out;
  for (size_t q = 0; q < tips.size() && q < sc.tipGrowth.size(); ++q) {
    const TipMeasure &m = tips[q];
    TipGrowth &g = sc.tipGrowth[q];
    if (g.stopped) continue;
    const double Gc = sc.materialAt(m.tip).Gc;
    if (std::isnan(m.G_J)) { // no J domain fits: the tip cannot be measured, so it stops (said)
      g.stopped = true;
      stops.push_back("crack " + std::to_string(g.crack) + " tip " + std::to_string(g.end) +
                      " at " + fmt(m.tip[0]) + "," + fmt(m.tip[1]) + " stops growing at t " +
                      fmt(t) + " s: no J-integral domain fits at the tip (it is within " +
                      fmt(kJMinCells) + " cells of its body's edge, a hole or a crack)");
      continue;
    }
    if (!(Gc > 0 && m.G_J >= Gc)) continue;
    Crack &c = sc.cracks[static_cast<size_t>(g.crack)];
    const size_t n = c.points.size();
    const std::array<double, 2> tip = g.end == 0 ? c.points[0] : c.points[n - 1];
    const std::array<double, 2> &back = g.end == 0 ? c.points[1] : c.points[n - 2];
    const double dx = tip[0] - back[0], dy = tip[1] - back[1], len = std::hypot(dx, dy);
    const double tt[2] = {dx / len, dy / len}, nn[2] = {-tt[1], tt[0]};
    const double theta =
        std::fabs(m.KII_J) <= kModeIIRoundoff * std::fabs(m.KI_J) ? 0.0 : mtsKink(m.KI_J, m.KII_J);
    const double ct = std::cos(theta), st = std::sin(theta);
    const std::array<double, 2> x = {tip[0] + g.step * (ct * tt[0] + st * nn[0]),
                                     tip[1] + g.step * (ct * tt[1] + st * nn[1])};
    const std::string why = refusal(sc, g, tip, x);
    if (!why.empty()) {
      g.stopped = true;
      stops.push_back("crack " + std::to_string(g.crack) + " tip " + std::to_string(g.end) +
                      " at " + fmt(tip[0]) + "," + fmt(tip[1]) + " stops growing at t " + fmt(t) +
                      " s: " + why);
      continue;
    }
    if (g.end == 0)
      c.points.insert(c.points.begin(), x);
    else
      c.points.push_back(x);
    ++c.grown[g.end];
    GrowthRecord r;
    r.t = t;
    r.crack = g.crack;
    r.end = g.end;
    r.x[0] = x[0];
    r.x[1] = x[1];
    r.G = m.G_J;
    r.KI = m.KI_J;
    r.KII = m.KII_J;
    r.kink = theta * 180.0 / M_PI;
    out.push_back(r);
  }
  return out;
}

} // namespace gimp::cracks
