// The 3D scene from the options database (-gimp_dim 3). Every number is checked here; what the
// 3D solver does not model (the 2D shapes, cracks, corner and CPDI tracking, plane stress, the
// multi-rate step, checkpoints, ...) is refused in one line naming the option.
#include "gimp/input/scene.hpp"

#include "scene_options.hpp"

#include <algorithm>
#include <cmath>

namespace gimp {

using input::bad;
using input::checkChoice;
using input::fmtList;

namespace {

const char *const kSides[] = {"left", "right", "bottom", "top", "back", "front"};
const char *const kAxes[] = {"x", "y", "z"};

/// Options that exist for 2D scenes only (a prefix, then a family's suffix), refused in 3D.
void refuse2dOnly() {
  static const char *const exact[] = {"-gimp_cracks",
                                      "-gimp_crack_j_radius",
                                      "-gimp_plane",
                                      "-gimp_thickness",
                                      "-gimp_cut_cells",
                                      "-gimp_xpic_order",
                                      "-gimp_corner_size",
                                      "-gimp_multirate",
                                      "-gimp_hole_measure",
                                      "-gimp_hole_measure_load",
                                      "-gimp_restart",
                                      "-gimp_checkpoint_interval",

                                      "-gimp_grid_dump",
                                      "-gimp_stability_check",
                                      "-gimp_stability_interval",
                                      "-gimp_allow_unstable_dt",
                                      "-gimp_separation_threshold",

                                      "-gimp_memory_limit"};
  for (const char *o : exact) {
    PetscBool set = PETSC_FALSE;
    (void)PetscOptionsHasName(nullptr, nullptr, o, &set);
    if (set)
      throw InputError(std::string("option ") + o +
                       ": not available with -gimp_dim 3 (2D scenes only; docs/options.md, "
                       "*3D scenes*)");
  }
}

/// A per-body 2D-only option, refused in 3D.
void refuse2dBody(const std::string &p) {
  for (const char *tail : {"circle", "ellipse", "polygon", "file", "add_boxes", "add_circles",
                           "add_ellipses", "add_polygons", "holes", "hole_ellipses",
                           "hole_polygons", "hole_ppc", "hole_band", "spin"}) {
    PetscBool set = PETSC_FALSE;
    (void)PetscOptionsHasName(nullptr, nullptr, (p + tail).c_str(), &set);
    if (set)
      throw InputError("option " + p + tail +
                       ": a 2D body option, not available with -gimp_dim 3 (3D bodies: box, "
                       "sphere, cylinder, hole_boxes, hole_spheres, hole_cylinders)");
  }
}

/// A PETSc error while reading options (a value that is not a number, ...): readScene<3> returns
/// its code, and readOptionsOneLine turns PETSc's message into one line.
struct OptionsFailure {
  PetscErrorCode code;
};

/// fn(PetscOptionsObject) inside PetscOptionsBegin/End, so that -help lists what it reads (under
/// a title of its own: PETSc prints each title's block once).
template <class Fn> void withOptions(MPI_Comm comm, const std::string &opt, Fn &&fn) {
  const std::string title = "gimp 3D scene (" + opt + ")";
  auto inner = [&]() -> PetscErrorCode {
    PetscOptionsBegin(comm, nullptr, title.c_str(), "gimp");
    PetscCall(fn(PetscOptionsObject));
    PetscOptionsEnd();
    return PETSC_SUCCESS;
  };
  if (const PetscErrorCode ierr = inner()) throw OptionsFailure{ierr};
}

/// Whether the option was given.
bool given(const std::string &opt) {
  PetscBool set = PETSC_FALSE;
  (void)PetscOptionsHasName(nullptr, nullptr, opt.c_str(), &set);
  return set;
}

/// An option that acts only with another one: refused when given without it.
void needs(bool has, const std::string &opt, const std::string &what) {
  if (!has && given(opt)) bad(opt.substr(1), "(given)", "acts only with " + what);
}

/// An option of n reals (exactly n when given); returns whether it was given.
bool realsOpt(MPI_Comm comm, const std::string &opt, const char *help, double *v, int n,
              const char *what) {
  PetscReal buf[16] = {};
  PetscInt got = 16;
  PetscBool set = PETSC_FALSE;
  withOptions(comm, opt, [&](PetscOptionItems *PetscOptionsObject) {
    return PetscOptionsRealArray(opt.c_str(), help, "docs/options.md", buf, &got, &set);
  });
  if (!set) return false;
  if (got != n) bad(opt.substr(1), fmtList(buf, got), std::string("needs ") + what);
  std::copy(buf, buf + n, v);
  return true;
}

/// A list of reals in groups of `group` (any number of groups).
std::vector<double> realListOpt(MPI_Comm comm, const std::string &opt, const char *help, int group,
                                const char *what) {
  std::vector<PetscReal> buf(512);
  PetscInt got = static_cast<PetscInt>(buf.size());
  PetscBool set = PETSC_FALSE;
  withOptions(comm, opt, [&](PetscOptionItems *PetscOptionsObject) {
    return PetscOptionsRealArray(opt.c_str(), help, "docs/options.md", buf.data(), &got, &set);
  });
  if (!set) return {};
  if (got == 0 || got % group != 0 || got == static_cast<PetscInt>(buf.size()))
    bad(opt.substr(1), fmtList(buf.data(), got), std::string("needs ") + what);
  return {buf.begin(), buf.begin() + got};
}

double realOpt(MPI_Comm comm, const std::string &opt, const char *help, double def,
               bool *given = nullptr) {
  PetscReal v = def;
  PetscBool set = PETSC_FALSE;
  withOptions(comm, opt, [&](PetscOptionItems *PetscOptionsObject) {
    return PetscOptionsReal(opt.c_str(), help, "docs/options.md", v, &v, &set);
  });
  if (given) *given = set;
  return v;
}

PetscInt intOpt(MPI_Comm comm, const std::string &opt, const char *help, PetscInt def) {
  PetscInt v = def;
  withOptions(comm, opt, [&](PetscOptionItems *PetscOptionsObject) {
    return PetscOptionsInt(opt.c_str(), help, "docs/options.md", v, &v, nullptr);
  });
  return v;
}

bool boolOpt(MPI_Comm comm, const std::string &opt, const char *help, bool def) {
  PetscBool v = def ? PETSC_TRUE : PETSC_FALSE;
  withOptions(comm, opt, [&](PetscOptionItems *PetscOptionsObject) {
    return PetscOptionsBool(opt.c_str(), help, "docs/options.md", v, &v, nullptr);
  });
  return v;
}

/// One of `list` (checked first, so that a bad value is one line), as its index.
int choiceOpt(MPI_Comm comm, const std::string &opt, const char *help, const char *const *list,
              int n, int def) {
  if (checkChoice(opt, list, n)) throw InputError("option " + opt + ": cannot be read");
  PetscInt v = def;
  withOptions(comm, opt, [&](PetscOptionItems *PetscOptionsObject) {
    return PetscOptionsEList(opt.c_str(), help, "docs/options.md", list, n, list[def], &v, nullptr);
  });
  return static_cast<int>(v);
}

std::string stringOpt(MPI_Comm comm, const std::string &opt, const char *help,
                      const std::string &def) {
  char buf[PETSC_MAX_PATH_LEN];
  std::snprintf(buf, sizeof(buf), "%s", def.c_str());
  withOptions(comm, opt, [&](PetscOptionItems *PetscOptionsObject) {
    return PetscOptionsString(opt.c_str(), help, "docs/options.md", buf, buf, sizeof(buf), nullptr);
  });
  return buf;
}

Ramp rampOpt(MPI_Comm comm, const std::string &opt, const char *help) {
  const std::vector<double> v = realListOpt(comm, opt, help, 2, "pairs t0,f0,t1,f1,... [s, -]");
  Ramp r;
  for (size_t i = 0; i < v.size(); i += 2) {
    if (i > 0 && !(v[i] > v[i - 2]))
      bad(opt.substr(1), fmtList(v.data(), static_cast<PetscInt>(v.size())),
          "the times must increase");
    r.t.push_back(v[i]);
    r.f.push_back(v[i + 1]);
  }
  return r;
}

void checkMaterial(const std::string &p, const Material &m) {
  if (!(m.E > 0)) bad(p + "E", formatNumber(m.E), "must be > 0 [Pa]");
  if (!(m.nu > -1 && m.nu < 0.5)) bad(p + "nu", formatNumber(m.nu), "must lie in (-1, 0.5) in 3D");
  if (!(m.rho > 0)) bad(p + "rho", formatNumber(m.rho), "must be > 0 [kg/m^3]");
}

Material readMaterial3(MPI_Comm comm, const std::string &p, const Material &base, bool &own) {
  static const char *const models[] = {"linear", "neohookean"};
  Material m = base;
  bool gE = false, gnu = false, grho = false;
  PetscBool gm = PETSC_FALSE;
  (void)PetscOptionsHasName(nullptr, nullptr, ("-" + p + "material").c_str(), &gm);
  m.model = choiceOpt(comm, "-" + p + "material", "Material model: linear (Jaumann) or neohookean",
                      models, 2, base.model == MaterialModel::NeoHookean) == 1
                ? MaterialModel::NeoHookean
                : MaterialModel::Linear;
  m.E = realOpt(comm, "-" + p + "E", "Young's modulus [Pa]", base.E, &gE);
  m.nu = realOpt(comm, "-" + p + "nu", "Poisson's ratio [-]", base.nu, &gnu);
  m.rho = realOpt(comm, "-" + p + "rho", "Density [kg/m^3]", base.rho, &grho);
  m.planeStrain = true; // lambda itself: the 3D model
  m.thickness = 1.0;
  own = gE || gnu || grho || gm;
  input::deriveMaterial(m);
  return m;
}

/// The face options of a traction or penalty condition: body, side, range.
Face<3> readFace(MPI_Comm comm, const std::string &p, const Scene<3> &sc) {
  Face<3> f;
  f.body = static_cast<int>(intOpt(comm, "-" + p + "body", "Body whose box face this is", 0));
  if (f.body < 0 || f.body >= static_cast<int>(sc.bodies.size()))
    bad(p + "body", std::to_string(f.body),
        "must be a body index 0.." + std::to_string(sc.bodies.size() - 1));
  f.side = choiceOpt(comm, "-" + p + "side",
                     "Face of the body's box: left, right (x), bottom, top (y), back, front (z)",
                     kSides, 6, 1);
  f.hasRange = realsOpt(comm, "-" + p + "range",
                        "Rectangle on the face: from,to along its first in-face axis, then the "
                        "second (in x, y, z order) [m]",
                        f.range.data(), 4, "4 values a0,a1,b0,b1 [m]");
  if (f.hasRange && !(f.range[0] < f.range[1] && f.range[2] < f.range[3]))
    bad(p + "range", fmtList(f.range.data(), 4), "needs a0 < a1 and b0 < b1 [m]");
  return f;
}

void readBodies3(MPI_Comm comm, Scene<3> &sc) {
  static const char *const shapes[] = {"box", "sphere", "cylinder"};
  static const char *const profiles[] = {"uniform", "sine_x"};
  const PetscInt nb = intOpt(comm, "-gimp_bodies", "Number of bodies -gimp_bodyK_*", 1);
  if (!sc.help && (nb < 1 || nb > 1000))
    bad("gimp_bodies", std::to_string(nb), "must lie in 1..1000");
  sc.oneMaterial = true;
  for (PetscInt k = 0; k < (sc.help ? 1 : nb); ++k) {
    const std::string p = "gimp_body" + std::to_string(k) + "_";
    refuse2dBody("-" + p);
    Body<3> b;
    bool own = false;
    b.material = readMaterial3(comm, p, sc.material, own);
    if (own) {
      sc.oneMaterial = false;
      if (!sc.help) checkMaterial(p, b.material);
    }
    const int shape =
        choiceOpt(comm, "-" + p + "shape", "Body shape: box, sphere or cylinder", shapes, 3, 0);
    double v[6];
    // -help lists every shape's options.
    if (shape == 0 || sc.help) {
      b.kind = Body<3>::BoxShape;
      b.shapeOption = "box";
      if (!realsOpt(comm, "-" + p + "box", "Body box x0,y0,z0,x1,y1,z1 [m]", b.box.data(), 6,
                    "6 values x0,y0,z0,x1,y1,z1 [m]") &&
          !sc.help)
        bad(p + "box", "(missing)", "a box body needs its box x0,y0,z0,x1,y1,z1 [m]");
      if (!sc.help && !(b.box[0] < b.box[3] && b.box[1] < b.box[4] && b.box[2] < b.box[5]))
        bad(p + "box", fmtList(b.box.data(), 6), "needs x0 < x1, y0 < y1 and z0 < z1 [m]");
    }
    if (shape == 1 || sc.help) {
      b.kind = Body<3>::RoundShape;
      b.shapeOption = "sphere";
      b.round.kind = Solid::Sphere;
      if (!realsOpt(comm, "-" + p + "sphere", "Sphere cx,cy,cz,r [m]", v, 4,
                    "4 values cx,cy,cz,r [m]") &&
          !sc.help)
        bad(p + "sphere", "(missing)", "a sphere body needs cx,cy,cz,r [m]");
      b.round.c = {v[0], v[1], v[2]};
      b.round.r = v[3];
      if (!sc.help && !(v[3] > 0)) bad(p + "sphere", fmtList(v, 4), "needs r > 0 [m]");
    }
    if (shape == 2 || sc.help) {
      b.kind = Body<3>::RoundShape;
      b.shapeOption = "cylinder";
      b.round.kind = Solid::Cylinder;
      b.round.axis =
          choiceOpt(comm, "-" + p + "cylinder_axis", "Cylinder axis: x, y or z", kAxes, 3, 2);
      if (!realsOpt(comm, "-" + p + "cylinder",
                    "Cylinder a,b,r,lo,hi: centre in the two other coordinates (x, y, z order), "
                    "radius, extent along the axis [m]",
                    v, 5, "5 values a,b,r,lo,hi [m]") &&
          !sc.help)
        bad(p + "cylinder", "(missing)", "a cylinder body needs a,b,r,lo,hi [m]");
      int q = 0;
      for (int a = 0; a < 3; ++a)
        b.round.c[a] = a == b.round.axis ? 0.0 : v[q++];
      b.round.r = v[2];
      b.round.lo = v[3];
      b.round.hi = v[4];
      if (!sc.help && !(v[2] > 0 && v[3] < v[4]))
        bad(p + "cylinder", fmtList(v, 5), "needs r > 0 and lo < hi [m]");
    }
    if (b.kind == Body<3>::RoundShape) b.box = b.round.box();
    const std::vector<double> hs =
        realListOpt(comm, "-" + p + "hole_spheres", "Spherical holes cx,cy,cz,r,... [m]", 4,
                    "groups cx,cy,cz,r [m]");
    for (size_t i = 0; i < hs.size(); i += 4) {
      Solid h;
      h.c = {hs[i], hs[i + 1], hs[i + 2]};
      h.r = hs[i + 3];
      if (!(h.r > 0)) bad(p + "hole_spheres", fmtList(&hs[i], 4), "needs r > 0 [m]");
      b.holes.push_back(h);
    }
    const std::vector<double> hb =
        realListOpt(comm, "-" + p + "hole_boxes", "Box holes x0,y0,z0,x1,y1,z1,... [m]", 6,
                    "groups x0,y0,z0,x1,y1,z1 [m]");
    for (size_t i = 0; i < hb.size(); i += 6) {
      Solid h;
      h.kind = Solid::BoxHole;
      std::copy(&hb[i], &hb[i] + 6, h.b.begin());
      if (!(h.b[0] < h.b[3] && h.b[1] < h.b[4] && h.b[2] < h.b[5]))
        bad(p + "hole_boxes", fmtList(&hb[i], 6), "needs x0 < x1, y0 < y1 and z0 < z1 [m]");
      b.holes.push_back(h);
    }
    const int haxis = choiceOpt(comm, "-" + p + "hole_cylinder_axis",
                                "Axis of the cylindrical holes: x, y or z", kAxes, 3, 2);
    const std::vector<double> hc =
        realListOpt(comm, "-" + p + "hole_cylinders",
                    "Cylindrical holes through the body a,b,r,...: centre in the two other "
                    "coordinates, radius [m]",
                    3, "groups a,b,r [m]");
    for (size_t i = 0; i < hc.size(); i += 3) {
      Solid h;
      h.kind = Solid::Cylinder;
      h.axis = haxis;
      int q = 0;
      for (int a = 0; a < 3; ++a)
        h.c[a] = a == haxis ? 0.0 : hc[i + q++];
      h.r = hc[i + 2];
      if (!(h.r > 0)) bad(p + "hole_cylinders", fmtList(&hc[i], 3), "needs r > 0 [m]");
      b.holes.push_back(h);
    }
    b.ppc = static_cast<int>(
        intOpt(comm, "-" + p + "ppc", "Particles per cell, a perfect cube n^3 (1, 8, 27, ...)", 8));
    const int n = static_cast<int>(std::lround(std::cbrt(static_cast<double>(b.ppc))));
    if (!sc.help && (b.ppc < 1 || n * n * n != b.ppc || n > 10))
      bad(p + "ppc", std::to_string(b.ppc), "must be a perfect cube n^3 with 1 <= n <= 10");
    realsOpt(comm, "-" + p + "velocity", "Initial velocity vx,vy,vz [m/s]", b.velocity.data(), 3,
             "3 values vx,vy,vz [m/s]");
    b.sineProfile =
        choiceOpt(
            comm, "-" + p + "velocity_profile",
            "uniform, or sine_x: v = velocity sin(k (X - x0)), X - x0 from the box's low x face",
            profiles, 2, 0) == 1;
    b.wavenumber = realOpt(comm, "-" + p + "wavenumber", "k of the sine profile [1/m]", 0.0);
    if (!sc.help) {
      needs(b.sineProfile, "-" + p + "wavenumber", "-" + p + "velocity_profile sine_x");
      needs(given("-" + p + "hole_cylinders"), "-" + p + "hole_cylinder_axis",
            "-" + p + "hole_cylinders");
      needs(b.round.kind == Solid::Cylinder && b.kind == Body<3>::RoundShape,
            "-" + p + "cylinder_axis", "-" + p + "shape cylinder");
    }
    if (!sc.help && b.sineProfile && !(b.wavenumber > 0))
      bad(p + "wavenumber", formatNumber(b.wavenumber), "must be > 0 [1/m] with the sine profile");
    sc.bodies.push_back(b);
  }
}

void readLoads3(MPI_Comm comm, Scene<3> &sc) {
  realsOpt(comm, "-gimp_gravity", "Body force per unit mass gx,gy,gz [m/s^2]", sc.gravity.data(), 3,
           "3 values gx,gy,gz [m/s^2]");
  const PetscInt nt = intOpt(comm, "-gimp_tractions", "Number of tractions -gimp_tractionK_*", 0);
  const PetscInt nd =
      intOpt(comm, "-gimp_dbcs", "Number of penalty conditions (Eq. 9) -gimp_dbcK_*", 0);
  const PetscInt nb = intOpt(comm, "-gimp_bcs", "Number of grid-node constraints -gimp_bcK_*", 0);
  const PetscInt np = intOpt(comm, "-gimp_probes", "Number of probes -gimp_probeK_*", 0);
  // The penalty options only with penalty conditions (otherwise unused, and refused as such).
  sc.penalty = 0.0;
  sc.penaltyTraction = true;
  if (nd > 0 || sc.help) {
    sc.penalty =
        realOpt(comm, "-gimp_penalty", "Penalty alpha of Eq. 9 [Pa/m] (0: automatic)", 0.0);
    sc.penaltyTraction = boolOpt(comm, "-gimp_penalty_traction",
                                 "Include the traction term sigma_p n of Eq. 9", true);
  }
  // -help lists one of each family.
  const bool help = sc.help;
  if (!help) {
    for (auto [n, o] : {std::pair{nt, "gimp_tractions"}, std::pair{nd, "gimp_dbcs"},
                        std::pair{nb, "gimp_bcs"}, std::pair{np, "gimp_probes"}})
      if (n < 0 || n > 1000) bad(o, std::to_string(n), "must lie in 0..1000");
    if (sc.penalty < 0) bad("gimp_penalty", formatNumber(sc.penalty), "must be >= 0 [Pa/m]");
  }
  for (PetscInt k = 0; k < (help ? 1 : nt); ++k) {
    const std::string p = "gimp_traction" + std::to_string(k) + "_";
    Traction<3> t;
    static_cast<Face<3> &>(t) = readFace(comm, p, sc);
    if (!realsOpt(comm, "-" + p + "value", "Traction tx,ty,tz at full load [Pa]", t.value.data(), 3,
                  "3 values tx,ty,tz [Pa]") &&
        !help)
      bad(p + "value", "(missing)", "each traction needs its value tx,ty,tz [Pa]");
    t.ramp = rampOpt(comm, "-" + p + "ramp", "Load factor table t0,f0,t1,f1,... [s, -]");
    t.hasDisk = realsOpt(comm, "-" + p + "disk",
                         "Load only the circle a,b,r of the face (centre in its in-face "
                         "coordinates, x, y, z order; radius) [m]",
                         t.disk.data(), 3, "3 values a,b,r [m]");
    if (t.hasDisk && !(t.disk[2] > 0))
      bad(p + "disk", fmtList(t.disk.data(), 3), "needs r > 0 [m]");
    sc.tractions.push_back(t);
  }
  static const char *const comps[] = {"x", "y", "z", "xy", "xz", "yz", "xyz"};
  for (PetscInt k = 0; k < (help ? 1 : nd); ++k) {
    const std::string p = "gimp_dbc" + std::to_string(k) + "_";
    DisplacementBC<3> d;
    static_cast<Face<3> &>(d) = readFace(comm, p, sc);
    const std::string c =
        comps[choiceOpt(comm, "-" + p + "components",
                        "Constrained components: x, y, z, xy, xz, yz or xyz", comps, 7, 6)];
    for (int a = 0; a < 3; ++a) {
      d.fix[a] = c.find(kAxes[a]) != std::string::npos;
      const std::string uo = "-" + p + "u" + kAxes[a];
      PetscBool given = PETSC_FALSE;
      (void)PetscOptionsHasName(nullptr, nullptr, uo.c_str(), &given);
      if (given && !d.fix[a])
        bad(uo.substr(1), "(given)",
            "component " + std::string(kAxes[a]) + " is not constrained by -" + p + "components " +
                c);
      d.u[a] = rampOpt(comm, uo, "Prescribed displacement table t0,u0,t1,u1,... [s, m]");
    }
    d.penaltyScale = realOpt(comm, "-" + p + "penalty_scale", "Multiplies -gimp_penalty here", 1.0);
    if (!(d.penaltyScale > 0))
      bad(p + "penalty_scale", formatNumber(d.penaltyScale), "must be > 0");
    sc.dbcs.push_back(d);
  }
  static const char *const types[] = {"fixed", "x", "y", "z", "roller"};
  for (PetscInt k = 0; k < (help ? 1 : nb); ++k) {
    const std::string p = "gimp_bc" + std::to_string(k) + "_";
    NodeBC<3> b;
    int given = 0;
    for (int a = 0; a < 3; ++a) {
      bool set = false;
      const double c =
          realOpt(comm, "-" + p + kAxes[a], "Plane of grid nodes x_a = c [m]", 0.0, &set);
      if (set) {
        b.axis = a;
        b.coord = c;
        ++given;
      }
    }
    if (given != 1 && !help)
      bad(p + "x", "(" + std::to_string(given) + " planes)",
          "each node constraint needs exactly one of -" + p + "x, -" + p + "y, -" + p + "z");
    const int type = choiceOpt(comm, "-" + p + "type",
                               "fixed (all components), x, y, z (that component only) or roller "
                               "(the normal component)",
                               types, 5, 0);
    for (int a = 0; a < 3; ++a)
      b.fix[a] = type == 0 || type == a + 1 || (type == 4 && a == b.axis);
    b.hasRange =
        realsOpt(comm, "-" + p + "range",
                 "Rectangle in the plane: from,to along its first axis, then the second [m]",
                 b.range.data(), 4, "4 values a0,a1,b0,b1 [m]");
    if (b.hasRange && !(b.range[0] < b.range[1] && b.range[2] < b.range[3]))
      bad(p + "range", fmtList(b.range.data(), 4), "needs a0 < a1 and b0 < b1 [m]");
    sc.bcs.push_back(b);
  }
  for (PetscInt k = 0; k < (help ? 1 : np); ++k) {
    const std::string p = "gimp_probe" + std::to_string(k) + "_";
    Probe<3> q;
    q.name = stringOpt(comm, "-" + p + "name", "Probe name", "probe" + std::to_string(k));
    if (!realsOpt(comm, "-" + p + "x", "Probe point x,y,z (the nearest particle) [m]", q.x.data(),
                  3, "3 values x,y,z [m]") &&
        !help)
      bad(p + "x", "(missing)", "each probe needs its point x,y,z [m]");
    if (!help && (q.name.empty() || q.name.find_first_of(",\" \t") != std::string::npos))
      bad(p + "name", q.name, "a probe name is a non-empty word without commas, quotes or spaces");
    for (const Probe<3> &o : sc.probes)
      if (!help && o.name == q.name) bad(p + "name", q.name, "another probe has this name");
    sc.probes.push_back(q);
  }
}

void readLevels3(MPI_Comm comm, Scene<3> &sc) {
  const PetscInt n = intOpt(comm, "-gimp_levels", "Number of grid levels", 1);
  if (!sc.help && (n < 1 || n > 8)) bad("gimp_levels", std::to_string(n), "must lie in 1..8");
  sc.levels.assign(1, LevelBox<3>{});
  std::copy(sc.domain.begin(), sc.domain.end(), sc.levels[0].box.begin());
  for (PetscInt k = 1; k < (sc.help ? 2 : n); ++k) {
    const std::string p = "gimp_level" + std::to_string(k) + "_";
    LevelBox<3> L;
    if (!realsOpt(comm, "-" + p + "box", "Box x0,y0,z0,x1,y1,z1 of this level [m]", L.box.data(), 6,
                  "6 values x0,y0,z0,x1,y1,z1 [m]") &&
        !sc.help)
      bad(p + "box", "(missing)", "each level > 0 needs its box x0,y0,z0,x1,y1,z1 [m]");
    const double ratio =
        realOpt(comm, "-" + p + "ratio", "Refinement ratio (an integer >= 2)", 2.0);
    if (!sc.help && !(ratio >= 2 && ratio <= 16 && ratio == std::round(ratio)))
      bad(p + "ratio", formatNumber(ratio), "must be an integer from 2 to 16");
    L.ratio = static_cast<int>(ratio);
    sc.levels.push_back(L);
  }
}

} // namespace

void readSolidSceneOptions(MPI_Comm comm, Scene<3> &sc);

template <> PetscErrorCode readScene<3>(MPI_Comm comm, Scene<3> &sc) {
  try {
    readSolidSceneOptions(comm, sc);
  } catch (const OptionsFailure &f) {
    return f.code;
  }
  return PETSC_SUCCESS;
}

void readSolidSceneOptions(MPI_Comm comm, Scene<3> &sc) {
  PetscBool help = PETSC_FALSE;
  (void)PetscOptionsHasHelp(nullptr, &help);
  sc.help = help;
  if (!sc.help) refuse2dOnly();
  sc.name = stringOpt(comm, "-gimp_scene", "Scene name (output/<name> by default)", "scene");
  sc.outputDir = stringOpt(comm, "-gimp_output_dir", "Output directory", "output/" + sc.name);
  sc.outputInterval = static_cast<int>(intOpt(
      comm, "-gimp_output_interval", "Steps between HDF5 field outputs (0: first and last)", 0));
  sc.particleDump = stringOpt(comm, "-gimp_particle_dump",
                              "Write the final particles as CSV (sorted by id) to this file", "");
  sc.historyInterval =
      static_cast<int>(intOpt(comm, "-gimp_history_interval", "Steps between history rows", 10));
  sc.sortInterval = static_cast<int>(
      intOpt(comm, "-gimp_sort_interval",
             "Steps between orderings of each rank's particles by level-0 cell (0: never)", 50));
  sc.monitorInterval =
      static_cast<int>(intOpt(comm, "-gimp_monitor_interval", "Steps between monitor lines", 0));
  if (!sc.help)
    input::checkRunIntervals(sc.outputInterval, sc.historyInterval, sc.monitorInterval,
                             sc.sortInterval);
  bool own = false;
  sc.material = readMaterial3(comm, "gimp_", Material{}, own);
  bool sceneE = false, sceneRho = false;
  (void)realOpt(comm, "-gimp_E", "", 0.0, &sceneE);
  (void)realOpt(comm, "-gimp_rho", "", 0.0, &sceneRho);
  readBodies3(comm, sc);
  if (!sc.help) {
    if (sc.oneMaterial || (sceneE && sceneRho))
      checkMaterial("gimp_", sc.material);
    else if (!sceneE || !sceneRho)
      for (size_t k = 0; k < sc.bodies.size(); ++k)
        checkMaterial("gimp_body" + std::to_string(k) + "_", sc.bodies[k].material);
  }
  sc.h = realOpt(comm, "-gimp_h", "Cell size of level 0 [m]", 0.0);
  sc.pad =
      intOpt(comm, "-gimp_pad", "Cells of padding around the bodies for the default domain", 2);
  sc.domainGiven = realsOpt(comm, "-gimp_domain", "Grid domain x0,y0,z0,x1,y1,z1 [m]",
                            sc.domain.data(), 6, "6 values x0,y0,z0,x1,y1,z1 [m]");
  if (!sc.help) {
    if (!(sc.h > 0)) bad("gimp_h", formatNumber(sc.h), "must be > 0 [m]");
    if (sc.pad < 0) bad("gimp_pad", std::to_string(sc.pad), "must be >= 0");
    if (!sc.domainGiven) {
      // The bodies' bounding box on the grid lines of x = 0, padded by pad cells.
      for (int a = 0; a < 3; ++a) {
        double lo = 1e300, hi = -1e300;
        for (const Body<3> &b : sc.bodies) {
          lo = std::min(lo, b.box[a]);
          hi = std::max(hi, b.box[3 + a]);
        }
        sc.domain[a] = (std::floor(lo / sc.h + 1e-9) - sc.pad) * sc.h;
        sc.domain[3 + a] = (std::ceil(hi / sc.h - 1e-9) + sc.pad) * sc.h;
      }
    }
    for (int a = 0; a < 3; ++a) {
      const double n = (sc.domain[3 + a] - sc.domain[a]) / sc.h;
      if (std::fabs(n - std::round(n)) > 1e-6 * std::max(1.0, n))
        bad("gimp_domain", fmtList(sc.domain.data(), 6),
            std::string("its extent along ") + kAxes[a] + " (" +
                formatNumber(sc.domain[3 + a] - sc.domain[a]) +
                " m) is not a whole number of cells of -gimp_h " + formatNumber(sc.h));
      if (!(std::round(n) >= 2))
        bad("gimp_domain", fmtList(sc.domain.data(), 6),
            "needs at least 2 cells of -gimp_h along each axis");
    }
    // Every body inside the grid: nothing of a body is dropped at the domain's faces.
    for (size_t k = 0; k < sc.bodies.size(); ++k) {
      const BoxOf<3> &b = sc.bodies[k].box;
      for (int a = 0; a < 3; ++a)
        if (b[a] < sc.domain[a] - 1e-9 * sc.h || b[3 + a] > sc.domain[3 + a] + 1e-9 * sc.h) {
          const std::string o = "gimp_body" + std::to_string(k) + "_" + sc.bodies[k].shapeOption;
          bad(o, fmtList(b.data(), 6),
              "the body (its box " + fmtList(b.data(), 6) + ") must lie inside -gimp_domain " +
                  fmtList(sc.domain.data(), 6));
        }
    }
  }
  readLevels3(comm, sc);
  readLoads3(comm, sc);
  static const char *const updates[] = {"usf", "usl", "musl"};
  static const char *const transfers[] = {"flip", "apic", "xpic"};
  static const char *const trackings[] = {"none", "strain", "stretch", "corners", "cpdi", "cpdi2"};
  const int u = choiceOpt(comm, "-gimp_update", "Update scheme: usl or musl (3D)", updates, 3, 2);
  const int t =
      choiceOpt(comm, "-gimp_transfer", "Velocity transfer: flip or apic (3D)", transfers, 3, 1);
  const int tr =
      choiceOpt(comm, "-gimp_tracking", "Particle domain: none or stretch (3D)", trackings, 6, 2);
  bool flipGiven = false, cutoffGiven = false;
  sc.flip = realOpt(comm, "-gimp_flip", "FLIP fraction with -gimp_transfer flip", 1.0, &flipGiven);
  sc.halfStepStart =
      boolOpt(comm, "-gimp_half_step_start", "Start the leapfrog with a half kick", true);
  sc.damping = realOpt(comm, "-gimp_damping", "Damping coefficient d of Eq. 16 [1/s]", 0.0);
  sc.cfl = realOpt(comm, "-gimp_cfl", "Default time step as a fraction of h_min / c_p", 0.3);
  sc.massCutoff = realOpt(comm, "-gimp_mass_cutoff",
                          "Nodes lighter than this fraction of the mean particle mass are empty",
                          1e-14, &cutoffGiven);
  static const char *const mmss[] = {"none", "skb1d"};
  sc.mms = choiceOpt(comm, "-gimp_mms", "Manufactured solution: none or skb1d (along x)", mmss, 2,
                     0) == 1
               ? Mms::AxialWave
               : Mms::None;
  sc.mmsAmplitude = realOpt(comm, "-gimp_mms_amplitude",
                            "Amplitude A of the manufactured solution [m]", sc.mmsAmplitude);
  if (sc.help) return;
  needs(sc.mms != Mms::None, "-gimp_mms_amplitude", "-gimp_mms skb1d");
  if (sc.mms != Mms::None && !(sc.mmsAmplitude > 0))
    bad("gimp_mms_amplitude", formatNumber(sc.mmsAmplitude), "must be > 0 [m]");
  needs(!sc.dbcs.empty(), "-gimp_penalty", "penalty conditions (-gimp_dbcs)");
  needs(!sc.dbcs.empty(), "-gimp_penalty_traction", "penalty conditions (-gimp_dbcs)");
  if (sc.mms == Mms::AxialWave &&
      (!sc.oneMaterial || sc.material.model != MaterialModel::NeoHookean || sc.material.nu != 0.0))
    bad("gimp_mms", "skb1d",
        "needs one neo-Hookean material with -gimp_nu 0 (the 1D solution's model)");
  if (u == 0) bad("gimp_update", "usf", "3D scenes take usl or musl");
  if (t == 2) bad("gimp_transfer", "xpic", "3D scenes take flip or apic");
  if (tr != 0 && tr != 2) bad("gimp_tracking", trackings[tr], "3D scenes take none or stretch");
  sc.update = u == 1 ? Update::USL : Update::MUSL;
  sc.transfer = t == 0 ? Transfer::Flip : Transfer::Apic;
  sc.tracking = tr == 0 ? Tracking::None : Tracking::Stretch;
  if (flipGiven && sc.transfer != Transfer::Flip)
    bad("gimp_flip", formatNumber(sc.flip), "only with -gimp_transfer flip");
  if (!(sc.flip >= 0 && sc.flip <= 1))
    bad("gimp_flip", formatNumber(sc.flip), "must lie in [0, 1]");
  if (!cutoffGiven) sc.massCutoff = MethodOptions::defaultMassCutoff(sc.transfer);
  if (!(sc.massCutoff >= 0 && sc.massCutoff < 1))
    bad("gimp_mass_cutoff", formatNumber(sc.massCutoff), "must lie in [0, 1)");
  if (!(sc.damping >= 0)) bad("gimp_damping", formatNumber(sc.damping), "must be >= 0 [1/s]");
  if (!(sc.cfl > 0 && sc.cfl <= 1)) bad("gimp_cfl", formatNumber(sc.cfl), "must lie in (0, 1]");
}

} // namespace gimp
