// Loads, constraints and probes of a scene in either dimension: the body force, tractions and
// penalty conditions (Eq. 9) on the faces of the bodies' boxes, node constraints on grid lines
// (2D) or planes (3D), and the probes.
#include "scene_options.hpp"

#include <algorithm>

namespace gimp::input {

namespace {

const char *const kAxes[] = {"x", "y", "z"};

/// Body, side and range of a face: gimp_<kind>K_body, _side, _range; p is "gimp_<kind>K_".
template <int D>
void readFace(const Options &o, const std::string &p, const Scene<D> &sc, Face<D> &f) {
  const PetscInt body = o.integer(p + "body", 0);
  const char *const sides[] = {"left", "right", "bottom", "top", "back", "front"};
  const std::string side = o.choice(p + "side", "right");
  const std::vector<double> r = o.reals(p + "range");
  if (o.help()) return;
  if (body < 0 || body >= static_cast<PetscInt>(sc.bodies.size()))
    Options::bad(p + "body", std::to_string(body),
                 "must name a body, 0 to " + std::to_string(sc.bodies.size() - 1));
  f.body = static_cast<int>(body);
  f.side = static_cast<int>(std::find(sides, sides + 6, side) - sides);
  f.hasRange = !r.empty();
  for (size_t i = 0; i < r.size(); i += 2)
    if (!(r[i + 1] > r[i]))
      Options::bad(p + "range", fmtList(r.data(), r.size()),
                   D == 2 ? "needs from,to with to > from [m]" : "needs a0 < a1 and b0 < b1 [m]");
  if (f.hasRange) std::copy(r.begin(), r.end(), f.range.begin());
}

template <int D> void readTraction(const Options &o, PetscInt k, Scene<D> &sc) {
  Traction<D> t;
  const std::string p = "gimp_traction" + std::to_string(k) + "_";
  readFace(o, p, sc, t);
  const std::vector<double> v = o.reals(p + "value", !o.help());
  t.ramp = o.ramp(p + "ramp");
  if constexpr (D == 3) {
    const std::vector<double> disk = o.reals(p + "disk");
    t.hasDisk = !disk.empty();
    if (t.hasDisk && !(disk[2] > 0))
      Options::bad(p + "disk", fmtList(disk.data(), 3), "needs r > 0 [m]");
    if (t.hasDisk) std::copy(disk.begin(), disk.end(), t.disk.begin());
  }
  if (o.help()) return;
  std::copy(v.begin(), v.end(), t.value.begin());
  sc.tractions.push_back(t);
}

/// The constrained components: x, y (, z) and their combinations.
template <int D> void readDisplacementBC(const Options &o, PetscInt k, Scene<D> &sc) {
  DisplacementBC<D> d;
  const std::string p = "gimp_dbc" + std::to_string(k) + "_";
  readFace(o, p, sc, d);
  const std::string comps = o.choice(p + "components", D == 2 ? "xy" : "xyz");
  for (int a = 0; a < D; ++a) {
    d.fix[a] = comps.find(kAxes[a]) != std::string::npos;
    d.u[a] = o.ramp(p + "u" + kAxes[a]);
    if (!o.help() && !d.fix[a] && !d.u[a].t.empty())
      Options::bad(p + "u" + kAxes[a], o.givenValue(p + "u" + kAxes[a]),
                   "this component is not constrained (-" + p + "components " + comps + ")");
  }
  d.penaltyScale = o.real(p + "penalty_scale", 1.0);
  if (!o.help()) sc.dbcs.push_back(d);
}

template <int D> void readNodeBC(const Options &o, PetscInt k, Scene<D> &sc) {
  NodeBC<D> b;
  const std::string p = "gimp_bc" + std::to_string(k) + "_";
  int planes = 0;
  for (int a = 0; a < D; ++a) {
    bool set = false;
    const double c = o.real(p + kAxes[a], 0.0, &set);
    if (!set) continue;
    b.axis = a;
    b.coord = c;
    ++planes;
  }
  const std::string type = o.choice(p + "type", "fixed");
  const std::vector<double> r = o.reals(p + "range");
  if (o.help()) return;
  if (planes != 1) {
    std::string one = "-" + p + "x";
    for (int a = 1; a < D; ++a)
      one += (a + 1 < D ? ", -" : " or -") + p + kAxes[a];
    Options::bad(p + "x", planes ? "and another axis given" : "(missing)",
                 "give exactly one of " + one);
  }
  for (int c = 0; c < D; ++c)
    b.fix[c] = type == "fixed" || (type == "roller" && c == b.axis) || type == kAxes[c];
  b.hasRange = !r.empty();
  for (size_t i = 0; i < r.size(); i += 2)
    if (!(r[i + 1] > r[i]))
      Options::bad(p + "range", fmtList(r.data(), r.size()),
                   D == 2 ? "needs from,to with to > from [m]" : "needs a0 < a1 and b0 < b1 [m]");
  if (b.hasRange) std::copy(r.begin(), r.end(), b.range.begin());
  sc.bcs.push_back(b);
}

template <int D> void readProbe(const Options &o, PetscInt k, Scene<D> &sc) {
  Probe<D> pr;
  const std::string p = "gimp_probe" + std::to_string(k) + "_";
  pr.name = o.word(p + "name", "probe" + std::to_string(k));
  const std::vector<double> x = o.reals(p + "x", !o.help());
  if (o.help()) return;
  if (pr.name.empty() || pr.name.find_first_of(",\" \t") != std::string::npos)
    Options::bad(p + "name", pr.name,
                 "a probe name is a non-empty word without commas, quotes or spaces");
  for (const Probe<D> &q : sc.probes)
    if (q.name == pr.name) Options::bad(p + "name", pr.name, "another probe has this name");
  std::copy(x.begin(), x.end(), pr.x.begin());
  sc.probes.push_back(pr);
}

} // namespace

template <int D> void readLoads(const Options &o, Scene<D> &sc) {
  const std::vector<double> g = o.reals("gimp_gravity");
  if (!g.empty()) std::copy(g.begin(), g.end(), sc.gravity.begin());
  const PetscInt nt = o.integer("gimp_tractions", 0), nd = o.integer("gimp_dbcs", 0),
                 nb = o.integer("gimp_bcs", 0), np = o.integer("gimp_probes", 0);
  sc.penalty = o.real("gimp_penalty", 0.0);
  sc.penaltyTraction = o.flag("gimp_penalty_traction", true);
  o.needs(nd > 0, "gimp_penalty", "penalty conditions (-gimp_dbcs > 0)");
  o.needs(nd > 0, "gimp_penalty_traction", "penalty conditions (-gimp_dbcs > 0)");
  // -help lists one of each family.
  for (PetscInt k = 0; k < (o.help() ? 1 : nt); ++k)
    readTraction(o, k, sc);
  for (PetscInt k = 0; k < (o.help() ? 1 : nd); ++k)
    readDisplacementBC(o, k, sc);
  for (PetscInt k = 0; k < (o.help() ? 1 : nb); ++k)
    readNodeBC(o, k, sc);
  for (PetscInt k = 0; k < (o.help() ? 1 : np); ++k)
    readProbe(o, k, sc);
}

template void readLoads<2>(const Options &, Scene<2> &);
template void readLoads<3>(const Options &, Scene<3> &);

} // namespace gimp::input
