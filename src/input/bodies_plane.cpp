// Plane bodies (2D): a rectangle, circle, ellipse, polygon or particle file, shapes joined to it
// (a union), its circular, elliptic and polygonal holes, particles per cell, initial velocity and
// spin, and its own material; the checks of the bodies against each other and the domain.
#include "gimp/input/particle_file.hpp"
#include "scene_options.hpp"

#include <algorithm>
#include <cmath>

namespace gimp::input {

namespace {

/// The polygons p<name>J, J = 0 .. count - 1, each a simple polygon of at most 200 vertices,
/// appended to `out`.
void readPolygons(const Options &o, const std::string &p, const std::string &name, PetscInt count,
                  std::vector<Shape> &out) {
  for (PetscInt j = 0; j < (o.help() ? 1 : count); ++j) {
    const std::string opt = p + name + std::to_string(j);
    const std::vector<double> xy = o.reals(opt, !o.help());
    if (o.help()) continue;
    if (xy.size() > 400) Options::bad(opt, "(more than 200 vertices)", "at most 200 vertices");
    const std::string why = polygonProblem(xy);
    if (!why.empty()) Options::bad(opt, fmtList(xy.data(), xy.size()), why);
    out.push_back(Shape::polygon(xy));
  }
}

/// The union's shapes: where two overlap, the moments of their intersection must be exact (one
/// a rectangle, or two polygons one of which is convex), and no point lies in three of them.
void checkUnion(const std::string &q, const Body<2> &b, const std::vector<std::string> &names) {
  const std::vector<const Shape *> parts = b.parts();
  for (size_t i = 0; i < parts.size(); ++i)
    for (size_t j = i + 1; j < parts.size(); ++j)
      if (parts[j]->overlaps(*parts[i]) && !intersectable(*parts[i], *parts[j]))
        Options::bad(names[j], "(shape " + std::to_string(j) + " of the union)",
                     "overlaps shape " + std::to_string(i) +
                         ", and neither is a rectangle nor are both polygons with one convex: "
                         "their common part has no exact moments; split them so that they only "
                         "touch");
  if (parts.size() < 3) return;
  auto threeDeep = [&](double x, double y) { // strictly inside three shapes (b.box: the union's)
    int in = 0;
    for (const Shape *s : parts)
      in += s->strictlyInside(x, y) ? 1 : 0;
    return in >= 3;
  };
  double at[2];
  if (latticeFind(b.box, 256, threeDeep, at))
    Options::bad(
        q + "add_" +
            std::string(b.added.back().kind == Shape::Kind::Polygon ? "polygons" : "boxes"),
        "(at " + formatNumber(at[0]) + "," + formatNumber(at[1]) + ")",
        "three of the joined shapes overlap there: at most two may overlap at a point");
}

/// The shape of the option that names it (shape: rectangle, circle, ellipse, polygon, file).
void readMainShape(const Options &o, const std::string &q, const std::string &shape,
                   const Material &scene, Body<2> &b) {
  const char *names[5] = {"rectangle", "circle", "ellipse", "polygon", "file"};
  const char *opts[5] = {"box", "circle", "ellipse", "polygon", "file"};
  for (int k = 0; k < 5; ++k)
    if (shape != names[k] && o.given(q + opts[k]))
      Options::bad(q + opts[k], o.givenValue(q + opts[k]),
                   std::string("is for shape ") + names[k] + ", but -" + q + "shape is " + shape);
  if (shape == "file") {
    b.shapeOption = "file";
    b.file = o.word(q + "file", "");
    if (o.help()) return;
    // The particles as they are; the body's rectangle is their domains' bounding box.
    const BoxOf<2> bb = readFileBody<2>(o, q, scene.thickness, b.file, b.fromFile);
    b.shape = Shape::rectangle(bb[0], bb[1], bb[2], bb[3]);
    return;
  }
  const std::string opt = q + opts[std::find(names, names + 5, shape) - names];
  b.shapeOption = opt.substr(q.size());
  const std::vector<double> v = o.reals(opt);
  if (o.help()) return;
  if (v.empty())
    Options::bad(opt, "(missing)",
                 "each body of shape " + shape + " needs it" +
                     (shape == "rectangle" ? ": its rectangle x0,y0,x1,y1 [m]" : ""));
  if (shape == "rectangle") {
    if (!(v[2] > v[0] && v[3] > v[1]))
      Options::bad(opt, fmtList(v.data(), 4), "needs finite x1 > x0 and y1 > y0 (an empty body)");
    b.shape = Shape::rectangle(v[0], v[1], v[2], v[3]);
  } else if (shape == "circle") {
    if (!(v[2] > 0)) Options::bad(opt, fmtList(v.data(), 3), "needs a radius r > 0 [m]");
    b.shape = Shape::ellipse(v[0], v[1], v[2], v[2]);
  } else if (shape == "ellipse") {
    if (!(v[2] > 0) || !(v[3] > 0))
      Options::bad(opt, fmtList(v.data(), 4), "needs half-axes a, b > 0 [m]");
    b.shape = Shape::ellipse(v[0], v[1], v[2], v[3]);
  } else {
    if (v.size() > 400)
      Options::bad(opt, "(more than 200 vertices)", "at most 200 vertices (400 values)");
    const std::string why = polygonProblem(v);
    if (!why.empty()) Options::bad(opt, fmtList(v.data(), v.size()), why);
    b.shape = Shape::polygon(v);
  }
}

/// Shapes joined to the body (a union): boxes, circles, ellipses and polygons.
void readAdded(const Options &o, const std::string &q, Body<2> &b) {
  const std::vector<double> ab = o.reals(q + "add_boxes"), ac = o.reals(q + "add_circles"),
                            ae = o.reals(q + "add_ellipses");
  const PetscInt nap = o.integer(q + "add_polygons", 0);
  for (const auto &[name, v] :
       {std::pair{"add_boxes", &ab}, {"add_circles", &ac}, {"add_ellipses", &ae}})
    if (v->size() > 400) Options::bad(q + name, "(too many values)", "at most 100 shapes");
  for (size_t i = 0; i + 3 < ab.size(); i += 4) {
    if (!(ab[i + 2] > ab[i] && ab[i + 3] > ab[i + 1]))
      Options::bad(q + "add_boxes", fmtList(ab.data(), ab.size()),
                   "needs x1 > x0 and y1 > y0 in each");
    b.added.push_back(Shape::rectangle(ab[i], ab[i + 1], ab[i + 2], ab[i + 3]));
  }
  for (size_t i = 0; i + 2 < ac.size(); i += 3) {
    if (!(ac[i + 2] > 0))
      Options::bad(q + "add_circles", fmtList(ac.data(), ac.size()), "radii must be > 0");
    b.added.push_back(Shape::ellipse(ac[i], ac[i + 1], ac[i + 2], ac[i + 2]));
  }
  for (size_t i = 0; i + 3 < ae.size(); i += 4) {
    if (!(ae[i + 2] > 0) || !(ae[i + 3] > 0))
      Options::bad(q + "add_ellipses", fmtList(ae.data(), ae.size()), "half-axes must be > 0");
    b.added.push_back(Shape::ellipse(ae[i], ae[i + 1], ae[i + 2], ae[i + 3]));
  }
  readPolygons(o, q, "add_polygon", nap, b.added);
  if (o.help()) return;
  if (!b.file.empty())
    for (const char *name : {"add_boxes", "add_circles", "add_ellipses", "add_polygons"})
      if (o.given(q + name))
        Options::bad(q + name, o.givenValue(q + name),
                     "does not apply to a body of shape file: it cannot be joined to other "
                     "shapes");
  std::vector<std::string> names = {q + b.shapeOption};
  for (size_t i = 0; i < ab.size() / 4; ++i)
    names.push_back(q + "add_boxes");
  for (size_t i = 0; i < ac.size() / 3; ++i)
    names.push_back(q + "add_circles");
  for (size_t i = 0; i < ae.size() / 4; ++i)
    names.push_back(q + "add_ellipses");
  for (PetscInt j = 0; j < nap; ++j)
    names.push_back(q + "add_polygon" + std::to_string(j));
  b.box = b.shape.box;
  for (const Shape &s : b.added) {
    b.box[0] = std::min(b.box[0], s.box[0]);
    b.box[1] = std::min(b.box[1], s.box[1]);
    b.box[2] = std::max(b.box[2], s.box[2]);
    b.box[3] = std::max(b.box[3], s.box[3]);
  }
  checkUnion(q, b, names);
}

/// Circular, elliptic and polygonal holes.
void readHoles(const Options &o, const std::string &q, Body<2> &b) {
  const std::vector<double> holes = o.reals(q + "holes"), he = o.reals(q + "hole_ellipses");
  const PetscInt nhp = o.integer(q + "hole_polygons", 0);
  if (!b.file.empty() && (!holes.empty() || !he.empty() || nhp > 0)) {
    const std::string name = q + (!holes.empty() ? "holes"
                                  : !he.empty()  ? "hole_ellipses"
                                                 : "hole_polygons");
    Options::bad(name, o.givenValue(name),
                 "a body of shape file has no holes: leave its particles out of the file");
  }
  if (holes.size() > 300)
    Options::bad(q + "holes", "(more than 100 holes)", "at most 100 holes (300 values cx,cy,r)");
  for (size_t i = 0; i + 2 < holes.size(); i += 3) {
    if (!(holes[i + 2] > 0))
      Options::bad(q + "holes", fmtList(holes.data(), holes.size()), "needs radii > 0");
    b.holes.push_back({holes[i], holes[i + 1], holes[i + 2]});
  }
  if (he.size() > 400)
    Options::bad(q + "hole_ellipses", "(more than 100 holes)",
                 "at most 100 (400 values cx,cy,a,b)");
  for (size_t i = 0; i + 3 < he.size(); i += 4) {
    if (!(he[i + 2] > 0) || !(he[i + 3] > 0))
      Options::bad(q + "hole_ellipses", fmtList(he.data(), he.size()), "needs half-axes a, b > 0");
    b.shapeHoles.push_back(Shape::ellipse(he[i], he[i + 1], he[i + 2], he[i + 3]));
  }
  readPolygons(o, q, "hole_polygon", nhp, b.shapeHoles);
}

/// Holes lie inside the body (a rectangle's circular holes may cross its sides, as cut
/// planes of symmetry do) and do not overlap one another.
void checkHoles(const std::string &q, const Body<2> &b) {
  std::vector<Shape> all;
  std::vector<std::string> names; // the option that gave each hole
  for (const Hole &c : b.holes) {
    all.push_back(Shape::ellipse(c.cx, c.cy, c.r, c.r));
    names.push_back(q + "holes");
  }
  int polygons = 0;
  for (const Shape &h : b.shapeHoles) {
    all.push_back(h);
    names.push_back(h.kind == Shape::Kind::Ellipse
                        ? q + "hole_ellipses"
                        : q + "hole_polygon" + std::to_string(polygons++));
  }
  for (size_t i = 0; i < all.size(); ++i) {
    const bool mayCross =
        i < b.holes.size() && b.shape.kind == Shape::Kind::Rectangle && b.added.empty();
    if (!mayCross && !insideOfUnion(all[i], b.parts()))
      Options::bad(names[i], "(hole " + std::to_string(i) + ")",
                   "must lie inside the body's " + b.shapeOption +
                       " (only circular holes of a rectangle may cross its sides)");
    for (size_t j = 0; j < i; ++j)
      if (all[i].overlaps(all[j]))
        Options::bad(names[i], "(hole " + std::to_string(i) + ")",
                     "overlaps hole " + std::to_string(j) +
                         " of the same body: holes may touch but not overlap");
  }
}

/// Particles per cell, the hole band, the initial velocity, its profile and the spin.
void readSeedingAndMotion(const Options &o, const std::string &q, Body<2> &b) {
  const PetscInt ppc = o.integer(q + "ppc", 4), hppc = o.integer(q + "hole_ppc", 0);
  b.holeBand = o.real(q + "hole_band", 0.0);
  const std::vector<double> vel = o.reals(q + "velocity");
  bool k0Given = false;
  b.sineProfile = o.choice(q + "velocity_profile", "uniform") == "sine_x";
  b.wavenumber = o.real(q + "wavenumber", 0.0, &k0Given);
  const std::vector<double> spin = o.reals(q + "spin");
  b.spin = spin.empty() ? 0.0 : spin[0];
  if (o.help()) return;
  for (const char *name : {"ppc", "hole_ppc", "hole_band"})
    if (!b.file.empty() && o.given(q + name))
      Options::bad(q + name, o.givenValue(q + name),
                   "does not apply to a body of shape file: its particles are the file's rows");
  const bool holes = !b.holes.empty() || !b.shapeHoles.empty();
  for (const char *name : {"hole_ppc", "hole_band"})
    if (!holes && o.given(q + name))
      Options::bad(q + name, o.givenValue(q + name),
                   "acts on the cells next to a hole, and the body's " + b.shapeOption +
                       " has none");
  if (!isPerfectSquare(static_cast<int>(ppc)) || ppc > 64 * 64)
    Options::bad(q + "ppc", std::to_string(ppc),
                 "must be a perfect square (1, 4, 9, 16, 25, ...), at most 4096 (64 x 64)");
  if (hppc != 0 && (!isPerfectSquare(static_cast<int>(hppc)) || hppc > 64 * 64))
    Options::bad(q + "hole_ppc", std::to_string(hppc),
                 "must be 0 or a perfect square (1, 4, 9, ...), at most 4096");
  if (!vel.empty() && b.fromFile.hasVelocity)
    Options::bad(q + "velocity", fmtList(vel.data(), vel.size()),
                 "the particle file " + b.file +
                     " gives each particle's velocity (vx, vy): one or the other");
  b.ppc = static_cast<int>(ppc);
  b.holePpc = static_cast<int>(hppc ? hppc : ppc);
  if (!vel.empty()) b.velocity = {vel[0], vel[1]};
  if (b.sineProfile && !(b.wavenumber != 0))
    Options::bad(q + "wavenumber", formatNumber(b.wavenumber),
                 "velocity_profile sine_x needs a non-zero wavenumber [1/m]");
  if (!b.sineProfile && k0Given)
    Options::bad(q + "wavenumber", formatNumber(b.wavenumber),
                 "has no effect without -" + q + "velocity_profile sine_x");
}

bool sameMaterial(const Material &a, const Material &b) {
  return a.model == b.model && a.E == b.E && a.nu == b.nu && a.rho == b.rho;
}

} // namespace

void readBodies(const Options &o, Scene<2> &sc) {
  const PetscInt nb = o.integer("gimp_bodies", 1);
  for (PetscInt k = 0; k < (o.help() ? 1 : nb); ++k) {
    Body<2> b;
    const std::string q = "gimp_body" + std::to_string(k) + "_";
    readMainShape(o, q, o.choice(q + "shape", "rectangle"), sc.material, b);
    readAdded(o, q, b);
    readHoles(o, q, b);
    readSeedingAndMotion(o, q, b);
    readBodyMaterial(o, q, sc.material, sc.sceneE, sc.sceneRho, b.material);
    if (o.help()) continue;
    checkHoles(q, b);
    sc.bodies.push_back(b);
  }
  sc.oneMaterial = true;
  for (const Body<2> &b : sc.bodies)
    sc.oneMaterial = sc.oneMaterial && sameMaterial(b.material, sc.material);
}

} // namespace gimp::input
