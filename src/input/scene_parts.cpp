// Reading the parts of a scene: material, bodies, loads and constraints, probes, grid levels.
#include "gimp/input/particle_file.hpp"
#include "scene_options.hpp"

#include <cmath>

namespace gimp::input {

// Fixed-length lists are read with one spare place, so that an extra value is seen and refused.

namespace {

const char *const kSides[] = {"left", "right", "bottom", "top"};

} // namespace

PetscErrorCode readMaterial(MPI_Comm comm, Scene<2> &sc) {
  Material &m = sc.material;
  const char *models[] = {"linear", "neohookean"};
  const char *planes[] = {"strain", "stress"};
  PetscInt model = 0, plane = 0;
  PetscBool setE = PETSC_FALSE, setRho = PETSC_FALSE;
  PetscCall(checkChoice("-gimp_material", models, 2));
  PetscCall(checkChoice("-gimp_plane", planes, 2));
  PetscOptionsBegin(comm, nullptr, "Material", "gimp");
  PetscCall(PetscOptionsEList("-gimp_material",
                              "Constitutive model: linear (hypoelastic, Jaumann rate) or "
                              "neohookean (compressible)",
                              "docs/options.md", models, 2, models[0], &model, nullptr));
  PetscCall(
      PetscOptionsReal("-gimp_E", "Young's modulus [Pa]", "docs/options.md", m.E, &m.E, &setE));
  PetscCall(
      PetscOptionsReal("-gimp_nu", "Poisson's ratio [-]", "docs/options.md", m.nu, &m.nu, nullptr));
  PetscCall(PetscOptionsReal("-gimp_rho", "Mass density [kg/m^3]", "docs/options.md", m.rho, &m.rho,
                             &setRho));
  PetscCall(PetscOptionsEList("-gimp_plane", "Two-dimensional model: plane strain or plane stress",
                              "docs/options.md", planes, 2, planes[0], &plane, nullptr));
  PetscCall(PetscOptionsReal("-gimp_thickness", "Out-of-plane thickness [m]", "docs/options.md",
                             m.thickness, &m.thickness, nullptr));
  PetscOptionsEnd();
  m.model = model == 0 ? MaterialModel::Linear : MaterialModel::NeoHookean;
  m.planeStrain = plane == 0;
  if (sc.help) return PETSC_SUCCESS;
  // E and rho may be left to the bodies (-gimp_bodyK_E, _rho): a body that has neither its own
  // nor the scene's is refused in readBodyMaterial.
  sc.sceneE = setE == PETSC_TRUE;
  sc.sceneRho = setRho == PETSC_TRUE;
  if (setE && !(m.E > 0)) bad("gimp_E", formatNumber(m.E), "must be > 0 [Pa]");
  if (setRho && !(m.rho > 0)) bad("gimp_rho", formatNumber(m.rho), "must be > 0 [kg/m^3]");
  if (!(m.nu > -1.0 && m.nu < 0.5)) bad("gimp_nu", formatNumber(m.nu), "must lie in (-1, 0.5)");
  if (!(m.thickness > 0)) bad("gimp_thickness", formatNumber(m.thickness), "must be > 0 [m]");
  deriveMaterial(m);
  return PETSC_SUCCESS;
}

void deriveMaterial(Material &m) {
  m.mu = m.E / (2.0 * (1.0 + m.nu));
  m.lambda = m.E * m.nu / ((1.0 + m.nu) * (1.0 - 2.0 * m.nu));
  m.lambdaStar = m.lambdaEff();
}

namespace {

/// A body's own material: -gimp_bodyK_material, _E, _nu, _rho, each the scene's unless given
/// (the plane and the thickness are the scene's); p is "-gimp_bodyK_".
PetscErrorCode readBodyMaterial(MPI_Comm comm, const std::string &p, const Scene<2> &sc,
                                Body<2> &b) {
  b.material = sc.material;
  Material &m = b.material;
  const char *models[] = {"linear", "neohookean"};
  PetscInt model = m.model == MaterialModel::Linear ? 0 : 1;
  PetscBool setE = PETSC_FALSE, setRho = PETSC_FALSE;
  PetscCall(checkChoice(p + "material", models, 2));
  PetscOptionsBegin(comm, nullptr, ("Body material " + p + "*").c_str(), "gimp");
  PetscCall(PetscOptionsEList((p + "material").c_str(),
                              "The body's constitutive model (default: -gimp_material)",
                              "docs/options.md", models, 2, models[model], &model, nullptr));
  PetscCall(PetscOptionsReal((p + "E").c_str(),
                             "The body's Young's modulus (default: -gimp_E) [Pa]",
                             "docs/options.md", m.E, &m.E, &setE));
  PetscCall(PetscOptionsReal((p + "nu").c_str(),
                             "The body's Poisson's ratio (default: -gimp_nu) [-]",
                             "docs/options.md", m.nu, &m.nu, nullptr));
  PetscCall(PetscOptionsReal((p + "rho").c_str(),
                             "The body's mass density (default: -gimp_rho) [kg/m^3]",
                             "docs/options.md", m.rho, &m.rho, &setRho));
  PetscOptionsEnd();
  if (sc.help) return PETSC_SUCCESS;
  m.model = model == 0 ? MaterialModel::Linear : MaterialModel::NeoHookean;
  const std::string q = p.substr(1);
  if (!setE && !sc.sceneE)
    bad(q + "E", "(missing)",
        "the body has no Young's modulus: give it " + p + "E or the scene's -gimp_E [Pa]");
  if (!setRho && !sc.sceneRho)
    bad(q + "rho", "(missing)",
        "the body has no density: give it " + p + "rho or the scene's -gimp_rho [kg/m^3]");
  if (!(m.E > 0) || !std::isfinite(m.E)) bad(q + "E", formatNumber(m.E), "must be > 0 [Pa]");
  if (!(m.rho > 0) || !std::isfinite(m.rho))
    bad(q + "rho", formatNumber(m.rho), "must be > 0 [kg/m^3]");
  if (!(m.nu > -1.0 && m.nu < 0.5)) bad(q + "nu", formatNumber(m.nu), "must lie in (-1, 0.5)");
  deriveMaterial(m);
  return PETSC_SUCCESS;
}

bool sameMaterial(const Material &a, const Material &b) {
  return a.model == b.model && a.E == b.E && a.nu == b.nu && a.rho == b.rho;
}

} // namespace

namespace {

bool allFinite(const PetscReal *v, PetscInt n) {
  for (PetscInt i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

/// The body's shape from -gimp_bodyK_shape and the option it names (box, circle, ellipse,
/// polygon), and its elliptic and polygonal holes; p is "-gimp_bodyK_".
/// The polygons -gimp_bodyK_<name>J, J = 0 .. count - 1 (count from -gimp_bodyK_<name>s, at
/// most 20), each a simple polygon of at most 200 vertices, appended to `out`.
PetscErrorCode readPolygons(MPI_Comm comm, const std::string &p, const std::string &name,
                            PetscInt count, const char *what, std::vector<Shape> &out) {
  constexpr PetscInt kMaxPolygon = 400, kMaxPolygons = 20;
  if (count < 0 || count > kMaxPolygons)
    bad(p.substr(1) + name + "s", std::to_string(count),
        "must be 0 to " + std::to_string(kMaxPolygons));
  for (PetscInt j = 0; j < count; ++j) {
    const std::string o = p + name + std::to_string(j);
    PetscReal v[kMaxPolygon + 1] = {0};
    PetscInt n = kMaxPolygon + 1;
    PetscBool given = PETSC_FALSE;
    PetscOptionsBegin(comm, nullptr, o.c_str(), "gimp");
    PetscCall(PetscOptionsRealArray(o.c_str(), (std::string(what) + " x0,y0,x1,y1,... [m]").c_str(),
                                    "docs/options.md", v, &n, &given));
    PetscOptionsEnd();
    if (!given)
      bad(o.substr(1), "(missing)",
          "each of the " + std::to_string(count) + " " + name + "s needs its vertices");
    if (n > kMaxPolygon) bad(o.substr(1), "(more than 200 vertices)", "at most 200 vertices");
    const std::vector<double> xy(v, v + n);
    const std::string why = polygonProblem(xy);
    if (!why.empty()) bad(o.substr(1), fmtList(v, n), why);
    out.push_back(Shape::polygon(xy));
  }
  return PETSC_SUCCESS;
}

/// The union's shapes: where two overlap, the moments of their intersection must be exact (one
/// a rectangle, or two polygons one of which is convex), and no point lies in three of them.
void checkUnion(const std::string &q, const Body<2> &b, const std::vector<std::string> &names) {
  const std::vector<const Shape *> parts = b.parts();
  for (size_t i = 0; i < parts.size(); ++i)
    for (size_t j = i + 1; j < parts.size(); ++j)
      if (parts[j]->overlaps(*parts[i]) && !intersectable(*parts[i], *parts[j]))
        bad(names[j], "(shape " + std::to_string(j) + " of the union)",
            "overlaps shape " + std::to_string(i) +
                ", and neither is a rectangle nor are both polygons with one convex: their "
                "common part has no exact moments; split them so that they only touch");
  if (parts.size() < 3) return;
  auto threeDeep = [&](double x, double y) { // strictly inside three shapes (b.box: the union's)
    int in = 0;
    for (const Shape *s : parts)
      in += s->strictlyInside(x, y) ? 1 : 0;
    return in >= 3;
  };
  double at[2];
  if (latticeFind(b.box, 256, threeDeep, at))
    bad(q + "add_" +
            std::string(b.added.back().kind == Shape::Kind::Polygon ? "polygons" : "boxes"),
        "(at " + formatNumber(at[0]) + "," + formatNumber(at[1]) + ")",
        "three of the joined shapes overlap there: at most two may overlap at a point");
}

PetscErrorCode readShape(MPI_Comm comm, const std::string &p, const Scene<2> &sc, Body<2> &b) {
  const bool help = sc.help;
  const char *shapes[] = {"rectangle", "circle", "ellipse", "polygon", "file"};
  char file[PETSC_MAX_PATH_LEN] = "";
  PetscBool setFile = PETSC_FALSE;
  constexpr PetscInt kMaxPolygon = 400;
  PetscInt shape = 0, nbox = 5, ncirc = 4, nell = 5, npoly = kMaxPolygon + 1, nhe = 401, nhp = 0;
  PetscReal box[5] = {0}, circ[4] = {0}, ell[5] = {0}, poly[kMaxPolygon + 1] = {0}, he[401] = {0};
  PetscBool setBox = PETSC_FALSE, setCirc = PETSC_FALSE, setEll = PETSC_FALSE,
            setPoly = PETSC_FALSE, setHe = PETSC_FALSE, setAb = PETSC_FALSE, setAc = PETSC_FALSE,
            setAe = PETSC_FALSE;
  PetscReal ab[401] = {0}, ac[301] = {0}, ae[401] = {0};
  PetscInt nab = 401, nac = 301, nae = 401, nap = 0;
  PetscCall(checkChoice(p + "shape", shapes, 5));
  PetscOptionsBegin(comm, nullptr, ("Body shape " + p + "*").c_str(), "gimp");
  PetscCall(PetscOptionsEList((p + "shape").c_str(),
                              "Shape of the body: rectangle (_box), circle (_circle), ellipse "
                              "(_ellipse), polygon (_polygon) or particles from a file (_file)",
                              "docs/options.md", shapes, 5, shapes[0], &shape, nullptr));
  PetscCall(PetscOptionsString((p + "file").c_str(),
                               "CSV file of the body's particles: x,y and lx,ly or V, optionally "
                               "vx,vy (shape file)",
                               "docs/options.md", file, file, sizeof(file), &setFile));
  PetscCall(PetscOptionsRealArray((p + "box").c_str(), "Body rectangle x0,y0,x1,y1 [m]",
                                  "docs/options.md", box, &nbox, &setBox));
  PetscCall(PetscOptionsRealArray((p + "circle").c_str(),
                                  "Body circle cx,cy,r [m] (shape circle)", "docs/options.md",
                                  circ, &ncirc, &setCirc));
  PetscCall(
      PetscOptionsRealArray((p + "ellipse").c_str(),
                            "Body ellipse cx,cy,a,b, half-axes a along x and b along y [m] "
                            "(shape ellipse)",
                            "docs/options.md", ell, &nell, &setEll));
  PetscCall(PetscOptionsRealArray((p + "polygon").c_str(),
                                  "Body polygon x0,y0,x1,y1,... (a simple polygon, at most 200 "
                                  "vertices) [m] (shape polygon)",
                                  "docs/options.md", poly, &npoly, &setPoly));
  PetscCall(PetscOptionsRealArray((p + "hole_ellipses").c_str(),
                                  "Elliptic holes inside the body: cx,cy,a,b,... [m]",
                                  "docs/options.md", he, &nhe, &setHe));
  PetscCall(PetscOptionsRealArray((p + "add_boxes").c_str(),
                                  "Rectangles joined to the body: x0,y0,x1,y1,... [m]",
                                  "docs/options.md", ab, &nab, &setAb));
  PetscCall(PetscOptionsRealArray((p + "add_circles").c_str(),
                                  "Circles joined to the body: cx,cy,r,... [m]", "docs/options.md",
                                  ac, &nac, &setAc));
  PetscCall(PetscOptionsRealArray((p + "add_ellipses").c_str(),
                                  "Ellipses joined to the body: cx,cy,a,b,... [m]",
                                  "docs/options.md", ae, &nae, &setAe));
  PetscCall(PetscOptionsInt((p + "add_polygons").c_str(),
                            "Number of polygons joined to the body (each _add_polygonJ)",
                            "docs/options.md", nap, &nap, nullptr));
  PetscCall(PetscOptionsInt((p + "hole_polygons").c_str(),
                            "Number of polygonal holes (each _hole_polygonJ, J = 0..N-1)",
                            "docs/options.md", nhp, &nhp, nullptr));
  PetscOptionsEnd();
  if (help) return PETSC_SUCCESS;
  const std::string q = p.substr(1);
  const bool set[5] = {setBox == PETSC_TRUE, setCirc == PETSC_TRUE, setEll == PETSC_TRUE,
                       setPoly == PETSC_TRUE, setFile == PETSC_TRUE};
  const char *opt[5] = {"box", "circle", "ellipse", "polygon", "file"};
  for (int k = 0; k < 5; ++k)
    if (set[k] && k != shape)
      bad(q + opt[k], "(given)",
          std::string("is for shape ") + shapes[k] + ", but " + q + "shape is " + shapes[shape]);
  if (!set[shape])
    bad(q + opt[shape], "(missing)",
        std::string("each body of shape ") + shapes[shape] + " needs it" +
            (shape == 0 ? ": its rectangle x0,y0,x1,y1 [m]" : ""));
  b.shapeOption = opt[shape];
  switch (shape) {
  case 0:
    if (nbox != 4) bad(q + "box", fmtList(box, nbox), "needs 4 values x0,y0,x1,y1 [m]");
    if (!allFinite(box, 4) || !(box[2] > box[0] && box[3] > box[1]))
      bad(q + "box", fmtList(box, 4), "needs finite x1 > x0 and y1 > y0 (an empty body)");
    b.shape = Shape::rectangle(box[0], box[1], box[2], box[3]);
    break;
  case 1:
    if (ncirc != 3) bad(q + "circle", fmtList(circ, ncirc), "needs 3 values cx,cy,r [m]");
    if (!allFinite(circ, 3) || !(circ[2] > 0))
      bad(q + "circle", fmtList(circ, 3), "needs finite values and a radius r > 0 [m]");
    b.shape = Shape::ellipse(circ[0], circ[1], circ[2], circ[2]);
    break;
  case 2:
    if (nell != 4) bad(q + "ellipse", fmtList(ell, nell), "needs 4 values cx,cy,a,b [m]");
    if (!allFinite(ell, 4) || !(ell[2] > 0) || !(ell[3] > 0))
      bad(q + "ellipse", fmtList(ell, 4), "needs finite values and half-axes a, b > 0 [m]");
    b.shape = Shape::ellipse(ell[0], ell[1], ell[2], ell[3]);
    break;
  case 4: {
    // The particles as they are; the body's rectangle is their domains' bounding box.
    b.file = file;
    PetscCall(readParticleFile(comm, p + "file", b.file, sc.material.thickness, b.fromFile));
    BoxOf<2> bb = {1e300, 1e300, -1e300, -1e300};
    for (const FileParticle &f : b.fromFile.particles) {
      bb[0] = std::min(bb[0], f.x - f.lx);
      bb[1] = std::min(bb[1], f.y - f.ly);
      bb[2] = std::max(bb[2], f.x + f.lx);
      bb[3] = std::max(bb[3], f.y + f.ly);
    }
    b.shape = Shape::rectangle(bb[0], bb[1], bb[2], bb[3]);
    if (setHe || nhp > 0)
      bad(q + (setHe ? "hole_ellipses" : "hole_polygons"), "(given)",
          "a body of shape file has no holes: leave its particles out of the file");
    break;
  }
  default: {
    if (npoly > kMaxPolygon)
      bad(q + "polygon", "(more than 200 vertices)", "at most 200 vertices (400 values)");
    const std::vector<double> xy(poly, poly + npoly);
    const std::string why = polygonProblem(xy);
    if (!why.empty()) bad(q + "polygon", fmtList(poly, npoly), why);
    b.shape = Shape::polygon(xy);
  }
  }
  // Shapes joined to the body (a union).
  auto groups = [&](const char *name, PetscBool set, PetscInt n, int per, PetscReal *v,
                    const char *what) {
    if (!set) return;
    if (n > 400 || n % per != 0)
      bad(q + name, n > 400 ? "(too many values)" : fmtList(v, n),
          std::string("needs groups of ") + std::to_string(per) + " values " + what +
              " (at most 100 shapes)");
    for (PetscInt i = 0; i + per - 1 < n; i += per)
      if (!allFinite(v + i, per)) bad(q + name, fmtList(v, n), "the values must be finite");
  };
  groups("add_boxes", setAb, nab, 4, ab, "x0,y0,x1,y1");
  groups("add_circles", setAc, nac, 3, ac, "cx,cy,r");
  groups("add_ellipses", setAe, nae, 4, ae, "cx,cy,a,b");
  for (PetscInt i = 0; setAb && i + 3 < nab; i += 4) {
    if (!(ab[i + 2] > ab[i] && ab[i + 3] > ab[i + 1]))
      bad(q + "add_boxes", fmtList(ab, nab), "needs x1 > x0 and y1 > y0 in each");
    b.added.push_back(Shape::rectangle(ab[i], ab[i + 1], ab[i + 2], ab[i + 3]));
  }
  for (PetscInt i = 0; setAc && i + 2 < nac; i += 3) {
    if (!(ac[i + 2] > 0)) bad(q + "add_circles", fmtList(ac, nac), "radii must be > 0");
    b.added.push_back(Shape::ellipse(ac[i], ac[i + 1], ac[i + 2], ac[i + 2]));
  }
  for (PetscInt i = 0; setAe && i + 3 < nae; i += 4) {
    if (!(ae[i + 2] > 0) || !(ae[i + 3] > 0))
      bad(q + "add_ellipses", fmtList(ae, nae), "half-axes must be > 0");
    b.added.push_back(Shape::ellipse(ae[i], ae[i + 1], ae[i + 2], ae[i + 3]));
  }
  PetscCall(readPolygons(comm, p, "add_polygon", nap, "Polygon joined to the body", b.added));
  if (!b.added.empty() && shape == 4)
    bad(q + "add_boxes", "(given)", "a body of shape file cannot be joined to other shapes");
  std::vector<std::string> names = {q + b.shapeOption};
  const char *kinds[3] = {"add_boxes", "add_circles", "add_ellipses"};
  const PetscInt counts[3] = {setAb ? nab / 4 : 0, setAc ? nac / 3 : 0, setAe ? nae / 4 : 0};
  for (int g = 0; g < 3; ++g)
    for (PetscInt i = 0; i < counts[g]; ++i)
      names.push_back(q + kinds[g]);
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
  // Elliptic and polygonal holes: inside the shape, apart from each other.
  if (setHe && nhe > 400)
    bad(q + "hole_ellipses", "(more than 100 holes)", "at most 100 (400 values cx,cy,a,b)");
  if (setHe && nhe % 4 != 0)
    bad(q + "hole_ellipses", fmtList(he, nhe), "needs groups of 4 values cx,cy,a,b");
  for (PetscInt i = 0; setHe && i + 3 < nhe; i += 4) {
    if (!allFinite(he + i, 4) || !(he[i + 2] > 0) || !(he[i + 3] > 0))
      bad(q + "hole_ellipses", fmtList(he, nhe), "needs finite values and half-axes a, b > 0");
    b.shapeHoles.push_back(Shape::ellipse(he[i], he[i + 1], he[i + 2], he[i + 3]));
  }
  PetscCall(readPolygons(comm, p, "hole_polygon", nhp, "Polygonal hole", b.shapeHoles));
  return PETSC_SUCCESS;
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
      bad(names[i], "(hole " + std::to_string(i) + ")",
          "must lie inside the body's " + b.shapeOption +
              " (only circular holes of a rectangle may cross its sides)");
    for (size_t j = 0; j < i; ++j)
      if (all[i].overlaps(all[j]))
        bad(names[i], "(hole " + std::to_string(i) + ")",
            "overlaps hole " + std::to_string(j) +
                " of the same body: holes may touch but not overlap");
  }
}

} // namespace

PetscErrorCode readBodies(MPI_Comm comm, Scene<2> &sc) {
  PetscInt nb = 1;
  PetscOptionsBegin(comm, nullptr, "Bodies", "gimp");
  PetscCall(PetscOptionsInt("-gimp_bodies", "Number of bodies (each -gimp_bodyK_* with K = 0..N-1)",
                            "docs/options.md", nb, &nb, nullptr));
  PetscOptionsEnd();
  if (!sc.help && nb < 1) bad("gimp_bodies", std::to_string(nb), "must be >= 1");
  for (PetscInt k = 0; k < std::max<PetscInt>(nb, 1); ++k) {
    Body<2> b;
    const std::string p = "-gimp_body" + std::to_string(k) + "_";
    PetscReal holes[301] = {0}, vel[3] = {0, 0, 0};
    PetscInt nholes = 301, nvel = 3, ppc = 4, hppc = 0;
    PetscBool setHoles = PETSC_FALSE, setK0 = PETSC_FALSE;
    const char *profiles[] = {"uniform", "sine_x"};
    PetscInt profile = 0;
    PetscReal band = 0, k0 = 0, spin = 0;
    PetscCall(checkChoice(p + "velocity_profile", profiles, 2));
    PetscOptionsBegin(comm, nullptr, ("Body " + p + "*").c_str(), "gimp");
    PetscCall(PetscOptionsRealArray((p + "holes").c_str(),
                                    "Circular holes removed from the body: cx,cy,r,... [m]",
                                    "docs/options.md", holes, &nholes, &setHoles));
    PetscCall(PetscOptionsInt((p + "ppc").c_str(),
                              "Particles per cell (1, 4, 9, 16, 25, ...: n x n per cell)",
                              "docs/options.md", ppc, &ppc, nullptr));
    PetscCall(PetscOptionsInt((p + "hole_ppc").c_str(),
                              "Particles per cell in cells next to a hole (0: same as ppc)",
                              "docs/options.md", hppc, &hppc, nullptr));
    PetscCall(PetscOptionsReal((p + "hole_band").c_str(),
                               "Width of the band around each hole that gets hole_ppc "
                               "(0: one cell) [m]",
                               "docs/options.md", band, &band, nullptr));
    PetscCall(PetscOptionsRealArray((p + "velocity").c_str(), "Initial velocity vx,vy [m/s]",
                                    "docs/options.md", vel, &nvel, nullptr));
    PetscCall(PetscOptionsEList((p + "velocity_profile").c_str(),
                                "Initial velocity profile: uniform, or sine_x: "
                                "v = velocity sin(k (X - x0))",
                                "docs/options.md", profiles, 2, profiles[0], &profile, nullptr));
    PetscCall(PetscOptionsReal((p + "wavenumber").c_str(), "Wavenumber k of sine_x [1/m]",
                               "docs/options.md", k0, &k0, &setK0));
    PetscCall(PetscOptionsReal((p + "spin").c_str(),
                               "Initial rigid rotation about the box's centre, added to the "
                               "velocity: omega x (X - centre) [rad/s]",
                               "docs/options.md", spin, &spin, nullptr));
    PetscOptionsEnd();
    PetscCall(readShape(comm, p, sc, b));
    PetscCall(readBodyMaterial(comm, p, sc, b));
    if (sc.help) continue;
    const std::string q = p.substr(1);
    if (setHoles && nholes > 300)
      bad(q + "holes", "(more than 100 holes)", "at most 100 holes (300 values cx,cy,r)");
    if (setHoles && nholes % 3 != 0)
      bad(q + "holes", fmtList(holes, nholes), "needs triples cx,cy,r");
    for (PetscInt i = 0; setHoles && i + 2 < nholes; i += 3) {
      if (!allFinite(holes + i, 3) || !(holes[i + 2] > 0))
        bad(q + "holes", fmtList(holes, nholes), "needs finite values and radii > 0");
      b.holes.push_back({holes[i], holes[i + 1], holes[i + 2]});
    }
    if (!b.file.empty() && setHoles)
      bad(q + "holes", fmtList(holes, nholes),
          "a body of shape file has no holes: leave its particles out of the file");
    checkHoles(q, b);
    if (!isPerfectSquare(ppc))
      bad(q + "ppc", std::to_string(ppc), "must be a perfect square (1, 4, 9, 16, 25, ...)");
    if (hppc != 0 && !isPerfectSquare(hppc))
      bad(q + "hole_ppc", std::to_string(hppc), "must be 0 or a perfect square (1, 4, 9, ...)");
    if (band < 0) bad(q + "hole_band", formatNumber(band), "must be >= 0 [m]");
    if (nvel != 2 && nvel != 0) bad(q + "velocity", fmtList(vel, nvel), "needs 2 values vx,vy");
    if (nvel == 2 && b.fromFile.hasVelocity)
      bad(q + "velocity", fmtList(vel, nvel),
          "the particle file " + b.file +
              " gives each particle's velocity (vx, vy): one or the "
              "other");
    b.ppc = static_cast<int>(ppc);
    b.holePpc = static_cast<int>(hppc ? hppc : ppc);
    b.holeBand = band;
    b.velocity = {vel[0], vel[1]};
    if (profile == 1 && !(k0 != 0))
      bad(q + "wavenumber", formatNumber(k0),
          "velocity_profile sine_x needs a non-zero wavenumber [1/m]");
    if (profile != 1 && setK0)
      bad(q + "wavenumber", formatNumber(k0),
          "has no effect without -" + q + "velocity_profile sine_x");
    b.sineProfile = profile == 1;
    b.wavenumber = k0;
    b.spin = spin;
    sc.bodies.push_back(b);
  }
  sc.oneMaterial = true;
  for (const Body<2> &b : sc.bodies)
    sc.oneMaterial = sc.oneMaterial && sameMaterial(b.material, sc.material);
  return PETSC_SUCCESS;
}

namespace {

PetscErrorCode readRamp(MPI_Comm comm, const std::string &opt, Ramp &r, bool help) {
  PetscReal v[201] = {0};
  PetscInt n = 201;
  PetscBool set = PETSC_FALSE;
  PetscOptionsBegin(comm, nullptr, ("Table " + opt).c_str(), "gimp");
  PetscCall(PetscOptionsRealArray(opt.c_str(),
                                  "Load factor table t0,f0,t1,f1,... [s,-], linear in between, "
                                  "held after the last entry (default: constant 1)",
                                  "docs/options.md", v, &n, &set));
  PetscOptionsEnd();
  if (!set || help) return PETSC_SUCCESS;
  if (n > 200) bad(opt.substr(1), "(more than 100 pairs)", "at most 100 pairs t,f");
  if (n < 2 || n % 2) bad(opt.substr(1), fmtList(v, n), "needs pairs t,f (at least one)");
  for (PetscInt i = 0; i < n; i += 2) {
    if (i > 0 && !(v[i] > v[i - 2]))
      bad(opt.substr(1), fmtList(v, n), "times must increase strictly");
    r.t.push_back(v[i]);
    r.f.push_back(v[i + 1]);
  }
  return PETSC_SUCCESS;
}

/// Body, side and range of a segment: -gimp_<kind>K_body, _side, _range.
PetscErrorCode readSegment(MPI_Comm comm, const std::string &p, const char *what, Scene<2> &sc,
                           Face<2> &seg) {
  PetscInt body = 0, side = 1, nr = 3;
  PetscReal rng[3] = {0, 0, 0};
  PetscBool setR = PETSC_FALSE;
  PetscCall(checkChoice(p + "side", kSides, 4));
  PetscOptionsBegin(comm, nullptr, (std::string(what) + " segment " + p + "*").c_str(), "gimp");
  PetscCall(PetscOptionsInt((p + "body").c_str(), "Body it acts on", "docs/options.md", body,
                            &body, nullptr));
  PetscCall(PetscOptionsEList((p + "side").c_str(), "Side of the body's rectangle",
                              "docs/options.md", kSides, 4, kSides[1], &side, nullptr));
  PetscCall(PetscOptionsRealArray((p + "range").c_str(),
                                  "Part of the side it acts on: from,to along it [m]",
                                  "docs/options.md", rng, &nr, &setR));
  PetscOptionsEnd();
  if (sc.help) return PETSC_SUCCESS;
  const std::string q = p.substr(1);
  if (body < 0 || body >= static_cast<PetscInt>(sc.bodies.size()))
    bad(q + "body", std::to_string(body),
        "must name a body, 0 to " + std::to_string(sc.bodies.size() - 1));
  if (setR && (nr != 2 || !(rng[1] > rng[0])))
    bad(q + "range", fmtList(rng, nr), "needs from,to with to > from [m]");
  seg.body = static_cast<int>(body);
  seg.side = static_cast<int>(side);
  seg.hasRange = setR;
  seg.range = {rng[0], rng[1]};
  return PETSC_SUCCESS;
}

PetscErrorCode readTraction(MPI_Comm comm, PetscInt k, Scene<2> &sc) {
  Traction<2> t;
  const std::string p = "-gimp_traction" + std::to_string(k) + "_";
  PetscInt nv = 3;
  PetscReal val[3] = {0, 0, 0};
  PetscBool setV = PETSC_FALSE;
  PetscCall(readSegment(comm, p, "Traction", sc, t));
  PetscOptionsBegin(comm, nullptr, ("Traction " + p + "*").c_str(), "gimp");
  PetscCall(PetscOptionsRealArray((p + "value").c_str(),
                                  "Traction vector tx,ty at full load [Pa]", "docs/options.md",
                                  val, &nv, &setV));
  PetscOptionsEnd();
  PetscCall(readRamp(comm, p + "ramp", t.ramp, sc.help));
  if (sc.help) return PETSC_SUCCESS;
  if (!setV || nv != 2)
    bad(p.substr(1) + "value", setV ? fmtList(val, nv) : "(missing)", "needs tx,ty [Pa]");
  t.value = {val[0], val[1]};
  sc.tractions.push_back(t);
  return PETSC_SUCCESS;
}

PetscErrorCode readDisplacementBC(MPI_Comm comm, PetscInt k, Scene<2> &sc) {
  DisplacementBC<2> d;
  const std::string p = "-gimp_dbc" + std::to_string(k) + "_";
  const char *comps[] = {"x", "y", "xy"};
  PetscInt comp = 2;
  PetscReal scale = 1.0;
  PetscCall(readSegment(comm, p, "Penalty displacement condition", sc, d));
  PetscCall(checkChoice(p + "components", comps, 3));
  PetscOptionsBegin(comm, nullptr, ("Penalty displacement condition " + p + "*").c_str(), "gimp");
  PetscCall(PetscOptionsEList((p + "components").c_str(),
                              "Constrained displacement components: x, y or xy", "docs/options.md",
                              comps, 3, comps[2], &comp, nullptr));
  PetscCall(PetscOptionsReal((p + "penalty_scale").c_str(),
                             "Factor on -gimp_penalty for this segment [-]", "docs/options.md",
                             scale, &scale, nullptr));
  PetscOptionsEnd();
  PetscCall(readRamp(comm, p + "ux", d.u[0], sc.help));
  PetscCall(readRamp(comm, p + "uy", d.u[1], sc.help));
  if (sc.help) return PETSC_SUCCESS;
  if (!(scale > 0)) bad(p.substr(1) + "penalty_scale", formatNumber(scale), "must be > 0");
  d.fix[0] = comp != 1;
  d.fix[1] = comp != 0;
  for (int c = 0; c < 2; ++c)
    if (!d.fix[c] && !d.u[c].t.empty())
      bad(p.substr(1) + (c ? "uy" : "ux"), "(given)",
          "this component is not constrained (-" + p.substr(1) + "components " + comps[comp] + ")");
  d.penaltyScale = scale;
  sc.dbcs.push_back(d);
  return PETSC_SUCCESS;
}

PetscErrorCode readNodeBC(MPI_Comm comm, PetscInt k, Scene<2> &sc) {
  NodeBC<2> b;
  const std::string p = "-gimp_bc" + std::to_string(k) + "_";
  PetscReal x = 0, y = 0, rng[3] = {0, 0, 0};
  PetscBool setX = PETSC_FALSE, setY = PETSC_FALSE, setR = PETSC_FALSE;
  PetscInt nr = 3, type = 0;
  const char *types[] = {"fixed", "roller"};
  PetscCall(checkChoice(p + "type", types, 2));
  PetscOptionsBegin(comm, nullptr, ("Grid-node constraint " + p + "*").c_str(), "gimp");
  PetscCall(PetscOptionsReal((p + "x").c_str(),
                             "Constrain the grid nodes on the line x = value [m]",
                             "docs/options.md", x, &x, &setX));
  PetscCall(PetscOptionsReal((p + "y").c_str(),
                             "Constrain the grid nodes on the line y = value [m]",
                             "docs/options.md", y, &y, &setY));
  PetscCall(PetscOptionsEList((p + "type").c_str(),
                              "fixed (both components) or roller (normal component only)",
                              "docs/options.md", types, 2, types[0], &type, nullptr));
  PetscCall(PetscOptionsRealArray((p + "range").c_str(),
                                  "Part of the line that is constrained: from,to [m]",
                                  "docs/options.md", rng, &nr, &setR));
  PetscOptionsEnd();
  if (sc.help) return PETSC_SUCCESS;
  const std::string q = p.substr(1);
  if (setX == setY)
    bad(q + "x", setX ? "and -" + q + "y both given" : "(missing)",
        "give exactly one of -" + q + "x or -" + q + "y");
  if (setR && (nr != 2 || !(rng[1] > rng[0])))
    bad(q + "range", fmtList(rng, nr), "needs from,to with to > from [m]");
  b.axis = setX ? 0 : 1;
  b.coord = setX ? x : y;
  b.fix[0] = type == 0 || b.axis == 0;
  b.fix[1] = type == 0 || b.axis == 1;
  b.hasRange = setR;
  b.range = {rng[0], rng[1]};
  sc.bcs.push_back(b);
  return PETSC_SUCCESS;
}

PetscErrorCode readProbe(MPI_Comm comm, PetscInt k, Scene<2> &sc) {
  Probe<2> pr;
  const std::string p = "-gimp_probe" + std::to_string(k) + "_";
  char name[256] = "";
  PetscReal x[3] = {0, 0, 0};
  PetscInt nx = 3;
  PetscBool setX = PETSC_FALSE;
  pr.name = "probe" + std::to_string(k);
  PetscOptionsBegin(comm, nullptr, ("Probe " + p + "*").c_str(), "gimp");
  PetscCall(PetscOptionsString((p + "name").c_str(),
                               "Probe name in history.csv and summary.json", "docs/options.md",
                               pr.name.c_str(), name, sizeof(name), nullptr));
  PetscCall(PetscOptionsRealArray((p + "x").c_str(),
                                  "Initial position x,y; the probe follows the particle nearest "
                                  "to it [m]",
                                  "docs/options.md", x, &nx, &setX));
  PetscOptionsEnd();
  if (sc.help) return PETSC_SUCCESS;
  if (!setX || nx != 2)
    bad(p.substr(1) + "x", setX ? fmtList(x, nx) : "(missing)", "needs x,y [m]");
  pr.name = name;
  if (pr.name.empty() || pr.name.find_first_of(",\" \t") != std::string::npos)
    bad(p.substr(1) + "name", pr.name,
        "a probe name is a non-empty word without commas, quotes or spaces");
  for (const Probe<2> &o : sc.probes)
    if (o.name == pr.name) bad(p.substr(1) + "name", pr.name, "another probe has this name");
  pr.x = {x[0], x[1]};
  sc.probes.push_back(pr);
  return PETSC_SUCCESS;
}

} // namespace

PetscErrorCode readLoads(MPI_Comm comm, Scene<2> &sc) {
  PetscInt nt = 0, nbc = 0, np = 0, ndbc = 0;
  PetscReal g[3] = {0, 0, 0};
  PetscInt ng = 3;
  PetscBool setG = PETSC_FALSE, setPenalty = PETSC_FALSE, setPtrac = PETSC_FALSE;
  PetscBool ptrac = sc.penaltyTraction ? PETSC_TRUE : PETSC_FALSE;
  PetscOptionsBegin(comm, nullptr, "Loads and constraints", "gimp");
  PetscCall(PetscOptionsRealArray("-gimp_gravity", "Body force per unit mass gx,gy [m/s^2]",
                                  "docs/options.md", g, &ng, &setG));
  PetscCall(PetscOptionsInt("-gimp_tractions", "Number of traction loads -gimp_tractionK_*",
                            "docs/options.md", nt, &nt, nullptr));
  PetscCall(PetscOptionsInt("-gimp_bcs", "Number of grid-node constraints -gimp_bcK_*",
                            "docs/options.md", nbc, &nbc, nullptr));
  PetscCall(PetscOptionsInt("-gimp_dbcs",
                            "Number of penalty displacement conditions (Eq. 9) -gimp_dbcK_*",
                            "docs/options.md", ndbc, &ndbc, nullptr));
  PetscCall(PetscOptionsReal("-gimp_penalty",
                             "Penalty alpha of Eq. 9 [Pa/m] (0: 100 M / h_min, capped for "
                             "stability at rho h_min / (2 dt^2); M the P-wave modulus)",
                             "docs/options.md", sc.penalty, &sc.penalty, &setPenalty));
  PetscCall(PetscOptionsInt("-gimp_probes", "Number of probes -gimp_probeK_*", "docs/options.md",
                            np, &np, nullptr));
  PetscCall(PetscOptionsBool("-gimp_penalty_traction",
                             "Include the traction term sigma_p n of Eq. 9 (false: pure penalty)",
                             "docs/options.md", ptrac, &ptrac, &setPtrac));
  sc.penaltyTraction = ptrac;
  PetscOptionsEnd();
  if (!sc.help && setG && ng != 2)
    bad("gimp_gravity", fmtList(g, ng), "needs 2 values gx,gy [m/s^2]");
  sc.gravity = {g[0], g[1]};
  if (!sc.help) {
    if (nt < 0) bad("gimp_tractions", std::to_string(nt), "must be >= 0");
    if (nbc < 0) bad("gimp_bcs", std::to_string(nbc), "must be >= 0");
    if (np < 0) bad("gimp_probes", std::to_string(np), "must be >= 0");
    if (ndbc < 0) bad("gimp_dbcs", std::to_string(ndbc), "must be >= 0");
    if (sc.penalty < 0)
      bad("gimp_penalty", formatNumber(sc.penalty), "must be >= 0 [Pa/m] (0: automatic)");
    if (ndbc == 0 && setPenalty)
      bad("gimp_penalty", formatNumber(sc.penalty),
          "has no effect without penalty conditions (-gimp_dbcs > 0)");
    if (ndbc == 0 && setPtrac)
      bad("gimp_penalty_traction", ptrac ? "true" : "false",
          "has no effect without penalty conditions (-gimp_dbcs > 0)");
  }
  for (PetscInt k = 0; k < (sc.help ? 1 : nt); ++k)
    PetscCall(readTraction(comm, k, sc));
  for (PetscInt k = 0; k < (sc.help ? 1 : ndbc); ++k)
    PetscCall(readDisplacementBC(comm, k, sc));
  for (PetscInt k = 0; k < (sc.help ? 1 : nbc); ++k)
    PetscCall(readNodeBC(comm, k, sc));
  for (PetscInt k = 0; k < (sc.help ? 1 : np); ++k)
    PetscCall(readProbe(comm, k, sc));
  return PETSC_SUCCESS;
}

PetscErrorCode readLevels(MPI_Comm comm, Scene<2> &sc) {
  PetscInt n = 1;
  PetscOptionsBegin(comm, nullptr, "Grid levels", "gimp");
  PetscCall(PetscOptionsInt("-gimp_levels",
                            "Number of grid levels (1: uniform); level k > 0 is set by "
                            "-gimp_levelK_box and -gimp_levelK_ratio",
                            "docs/options.md", n, &n, nullptr));
  PetscOptionsEnd();
  if (!sc.help && (n < 1 || n > 8)) bad("gimp_levels", std::to_string(n), "must lie in 1..8");
  sc.levels.assign(1, LevelBox<2>{sc.domain, 1});
  for (PetscInt k = 1; k < (sc.help ? 2 : n); ++k) {
    const std::string p = "-gimp_level" + std::to_string(k) + "_";
    PetscReal box[5] = {0, 0, 0, 0, 0}, ratio = 2;
    PetscInt nbox = 5;
    PetscBool setBox = PETSC_FALSE;
    PetscOptionsBegin(comm, nullptr, ("Grid level " + p + "*").c_str(), "gimp");
    PetscCall(PetscOptionsRealArray((p + "box").c_str(),
                                    "Box x0,y0,x1,y1 of this level, corners on the parent "
                                    "level's grid lines [m]",
                                    "docs/options.md", box, &nbox, &setBox));
    PetscCall(PetscOptionsReal((p + "ratio").c_str(),
                               "Refinement ratio to the parent level (an integer >= 2)",
                               "docs/options.md", ratio, &ratio, nullptr));
    PetscOptionsEnd();
    if (sc.help) continue;
    const std::string q = p.substr(1);
    if (!setBox) bad(q + "box", "(missing)", "each level > 0 needs its box x0,y0,x1,y1 [m]");
    if (nbox != 4) bad(q + "box", fmtList(box, nbox), "needs 4 values x0,y0,x1,y1 [m]");
    if (!(ratio >= 2 && ratio <= 16 && ratio == std::round(ratio)))
      bad(q + "ratio", formatNumber(ratio), "must be an integer from 2 to 16");
    LevelBox<2> L;
    std::copy(box, box + 4, L.box.begin());
    L.ratio = static_cast<int>(ratio);
    sc.levels.push_back(L);
  }
  return PETSC_SUCCESS;
}

} // namespace gimp::input
