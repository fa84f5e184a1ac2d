// Reading the cracks of a scene (-gimp_cracks, -gimp_crackK_points): each polyline checked
// against itself, the bodies and the other cracks; each end classified as a tip or a mouth.
#include "scene_options.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gimp::input {

namespace {

/// The finest cell size among the levels whose box contains (x, y) (sc.h outside the grid).
double cellSizeAt(const Scene<2> &sc, double x, double y) {
  double h = sc.h, at = sc.h;
  for (size_t k = 0; k < sc.levels.size(); ++k) {
    const BoxOf<2> &b = sc.levels[k].box;
    h /= k ? sc.levels[k].ratio : 1;
    if (x >= b[0] && x <= b[2] && y >= b[1] && y <= b[3]) at = h;
  }
  return at;
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
void makeCrack(const Scene<2> &sc, const std::string &q, const PetscReal *v, PetscInt n, Crack &c) {
  const std::string all = fmtList(v, n);
  if (n < 4 || n % 2) bad(q, all, "needs pairs x,y of at least two points [m]");
  for (PetscInt i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) bad(q, all, "the coordinates must be finite numbers [m]");
  for (PetscInt i = 0; i < n; i += 2)
    c.points.push_back({v[i], v[i + 1]});
  double hmin = sc.h;
  for (size_t k = 1; k < sc.levels.size(); ++k)
    hmin /= sc.levels[k].ratio;
  const cracks::PolylineFault f = cracks::findFault(c, 1e-9 * hmin);
  const std::string i = std::to_string(f.i), j = std::to_string(f.j);
  if (f.kind == cracks::PolylineFault::ZeroLength)
    bad(q, all, "points " + i + " and " + j + " coincide: segments must have a length");
  if (f.kind == cracks::PolylineFault::FoldsBack)
    bad(q, all,
        "segments " + i + " and " + j +
            " fold back onto each other: a crack may not retrace itself");
  if (f.kind == cracks::PolylineFault::Intersects)
    bad(q, all, "segments " + i + " and " + j + " intersect: a crack may not cross itself");
  if (!reachesABody(sc, c, hmin))
    bad(q, all,
        "no point of the crack lies inside a body (in its box, not on an edge or in a hole): a "
        "crack must run into a body");
  for (int e = 0; e < 2; ++e) {
    const auto &x = e ? c.points.back() : c.points.front();
    c.tip[e] = strictlyInsideABody(sc, x[0], x[1]);
  }
}

/// A tip closer than one cell (the finest cell at the tip) to another crack.
void checkTips(const Scene<2> &sc) {
  for (size_t k = 0; k < sc.cracks.size(); ++k)
    for (int e = 0; e < 2; ++e) {
      const Crack &c = sc.cracks[k];
      if (!c.tip[e]) continue;
      const auto &x = e ? c.points.back() : c.points.front();
      const double h = cellSizeAt(sc, x[0], x[1]);
      for (size_t m = 0; m < sc.cracks.size(); ++m) {
        const double d = cracks::distance(sc.cracks[m], x[0], x[1]);
        if (m == k || d >= h) continue;
        std::vector<double> v;
        for (const auto &p : c.points)
          v.insert(v.end(), p.begin(), p.end());
        bad("gimp_crack" + std::to_string(k) + "_points",
            fmtList(v.data(), static_cast<PetscInt>(v.size())),
            "its tip " + formatNumber(x[0]) + "," + formatNumber(x[1]) + " is " + formatNumber(d) +
                " m from crack " + std::to_string(m) + ", less than one cell (" + formatNumber(h) +
                " m): a tip must be at least one cell from another crack");
      }
    }
}

} // namespace

PetscErrorCode readCracks(MPI_Comm comm, Scene<2> &sc) {
  PetscInt nc = 0;
  PetscBool setR = PETSC_FALSE;
  PetscOptionsBegin(comm, nullptr, "Cracks", "gimp");
  PetscCall(PetscOptionsInt("-gimp_cracks",
                            "Number of cracks, each given by -gimp_crackK_points, K = 0..N-1",
                            "docs/options.md", nc, &nc, nullptr));
  PetscCall(PetscOptionsReal("-gimp_crack_j_radius",
                             "Radius of the J-integral's domain around each tip [m] (default: 5 "
                             "finest cells)",
                             "docs/options.md", sc.crackJRadius, &sc.crackJRadius, &setR));
  PetscOptionsEnd();
  if (!sc.help && nc < 0) bad("gimp_cracks", std::to_string(nc), "must be >= 0");
  if (!sc.help && setR && !(sc.crackJRadius > 0 && std::isfinite(sc.crackJRadius)))
    bad("gimp_crack_j_radius", formatNumber(sc.crackJRadius), "must be a finite length > 0 [m]");
  if (!sc.help && setR && nc == 0)
    bad("gimp_crack_j_radius", formatNumber(sc.crackJRadius), "needs cracks (-gimp_cracks)");
  for (PetscInt k = 0; k < (sc.help ? 1 : nc); ++k) {
    const std::string p = "-gimp_crack" + std::to_string(k) + "_points";
    PetscReal v[201] = {0};
    PetscInt n = 201;
    PetscBool set = PETSC_FALSE;
    PetscOptionsBegin(comm, nullptr, ("Crack " + p).c_str(), "gimp");
    PetscCall(PetscOptionsRealArray(p.c_str(),
                                    "Crack polyline x0,y0,x1,y1,... [m]: an end strictly inside "
                                    "a body is a tip, one on or outside its edge a mouth",
                                    "docs/options.md", v, &n, &set));
    PetscOptionsEnd();
    if (sc.help) continue;
    if (!set) bad(p.substr(1), "(missing)", "each crack needs its polyline x0,y0,x1,y1,... [m]");
    if (n > 200) bad(p.substr(1), "(more than 100 points)", "at most 100 points (200 values) [m]");
    Crack c;
    makeCrack(sc, p.substr(1), v, n, c);
    sc.cracks.push_back(c);
  }
  if (!sc.help) checkTips(sc);
  return PETSC_SUCCESS;
}

} // namespace gimp::input
