// Solid bodies (3D): a box, sphere or cylinder along an axis, with box, spherical and
// cylindrical holes, n^3 particles per cell, an initial velocity and its own material; the
// check that each lies in the domain, and the default domain around them.
#include "scene_options.hpp"

#include <algorithm>
#include <cmath>

namespace gimp::input {

namespace {

int axisOf(const std::string &a) {
  return a == "x" ? 0 : a == "y" ? 1 : 2;
}

/// The body's solid from -gimp_bodyK_shape and the option it names; p is "gimp_bodyK_".
void readSolid(const Options &o, const std::string &p, Body<3> &b) {
  const std::string shape = o.choice(p + "shape", "box");
  for (const char *other : {"box", "sphere", "cylinder", "file"})
    if (shape != other && o.given(p + other))
      Options::bad(p + other, o.givenValue(p + other),
                   std::string("is for shape ") + other + ", but -" + p + "shape is " + shape);
  b.shapeOption = shape;
  b.kind = shape == "box" || shape == "file" ? Body<3>::BoxShape : Body<3>::RoundShape;
  const int axis = axisOf(o.choice(p + "cylinder_axis", "z"));
  o.needs(shape == "cylinder", p + "cylinder_axis", "-" + p + "shape cylinder");
  if (shape == "file") { // the particles as they are; the body's box is their domains' bounds
    b.file = o.word(p + "file", "");
    if (!o.help()) b.box = readFileBody<3>(o, p, 1.0, b.file, b.fromFile);
    return;
  }
  const std::vector<double> v = o.reals(p + shape, !o.help());
  if (o.help()) return;
  if (shape == "box") {
    std::copy(v.begin(), v.end(), b.box.begin());
    if (!(b.box[0] < b.box[3] && b.box[1] < b.box[4] && b.box[2] < b.box[5]))
      Options::bad(p + "box", fmtList(v.data(), 6), "needs x0 < x1, y0 < y1 and z0 < z1 [m]");
    return;
  }
  if (shape == "sphere") {
    b.round.kind = Solid::Sphere;
    b.round.c = {v[0], v[1], v[2]};
    b.round.r = v[3];
    if (!(v[3] > 0)) Options::bad(p + "sphere", fmtList(v.data(), 4), "needs r > 0 [m]");
  } else {
    b.round.kind = Solid::Cylinder;
    b.round.axis = axis;
    int q = 0;
    for (int a = 0; a < 3; ++a)
      b.round.c[a] = a == axis ? 0.0 : v[q++];
    b.round.r = v[2];
    b.round.lo = v[3];
    b.round.hi = v[4];
    if (!(v[2] > 0 && v[3] < v[4]))
      Options::bad(p + "cylinder", fmtList(v.data(), 5), "needs r > 0 and lo < hi [m]");
  }
  b.box = b.round.box();
}

/// Spherical, box and cylindrical holes.
void readSolidHoles(const Options &o, const std::string &p, Body<3> &b) {
  if (!b.file.empty())
    for (const char *name : {"hole_spheres", "hole_boxes", "hole_cylinders"})
      if (o.given(p + name))
        Options::bad(p + name, o.givenValue(p + name),
                     "a body of shape file has no holes: leave its particles out of the file");
  const std::vector<double> hs = o.reals(p + "hole_spheres");
  for (size_t i = 0; i < hs.size(); i += 4) {
    Solid h;
    h.c = {hs[i], hs[i + 1], hs[i + 2]};
    h.r = hs[i + 3];
    if (!(h.r > 0)) Options::bad(p + "hole_spheres", fmtList(&hs[i], 4), "needs r > 0 [m]");
    b.holes.push_back(h);
  }
  const std::vector<double> hb = o.reals(p + "hole_boxes");
  for (size_t i = 0; i < hb.size(); i += 6) {
    Solid h;
    h.kind = Solid::BoxHole;
    std::copy(&hb[i], &hb[i] + 6, h.b.begin());
    if (!(h.b[0] < h.b[3] && h.b[1] < h.b[4] && h.b[2] < h.b[5]))
      Options::bad(p + "hole_boxes", fmtList(&hb[i], 6), "needs x0 < x1, y0 < y1 and z0 < z1 [m]");
    b.holes.push_back(h);
  }
  const int axis = axisOf(o.choice(p + "hole_cylinder_axis", "z"));
  const std::vector<double> hc = o.reals(p + "hole_cylinders");
  o.needs(!hc.empty(), p + "hole_cylinder_axis", "-" + p + "hole_cylinders");
  for (size_t i = 0; i < hc.size(); i += 3) {
    Solid h;
    h.kind = Solid::Cylinder;
    h.axis = axis;
    int q = 0;
    for (int a = 0; a < 3; ++a)
      h.c[a] = a == axis ? 0.0 : hc[i + q++];
    h.r = hc[i + 2];
    if (!(h.r > 0)) Options::bad(p + "hole_cylinders", fmtList(&hc[i], 3), "needs r > 0 [m]");
    b.holes.push_back(h);
  }
}

/// Particles per cell, the initial velocity, its profile and the spin.
void readSolidMotion(const Options &o, const std::string &p, Body<3> &b) {
  const PetscInt ppc = o.integer(p + "ppc", 8), hppc = o.integer(p + "hole_ppc", 0);
  b.holeBand = o.real(p + "hole_band", 0.0);
  const std::vector<double> vel = o.reals(p + "velocity"), spin = o.reals(p + "spin");
  b.sineProfile = o.choice(p + "velocity_profile", "uniform") == "sine_x";
  b.wavenumber = o.real(p + "wavenumber", 0.0);
  if (o.help()) return;
  for (const char *name : {"ppc", "hole_ppc", "hole_band"})
    if (!b.file.empty() && o.given(p + name))
      Options::bad(p + name, o.givenValue(p + name),
                   "does not apply to a body of shape file: its particles are the file's rows");
  const bool curved = std::any_of(b.holes.begin(), b.holes.end(),
                                  [](const Solid &h) { return h.kind != Solid::BoxHole; });
  for (const char *name : {"hole_ppc", "hole_band"})
    if (!curved && o.given(p + name))
      Options::bad(p + name, o.givenValue(p + name),
                   "acts on the cells next to a spherical or cylindrical hole, and the body's " +
                       b.shapeOption + " has none");
  if (!vel.empty() && b.fromFile.hasVelocity)
    Options::bad(p + "velocity", fmtList(vel.data(), vel.size()),
                 "the particle file " + b.file +
                     " gives each particle's velocity (vx, vy, vz): one or the other");
  const int n = static_cast<int>(std::lround(std::cbrt(static_cast<double>(ppc))));
  if (ppc < 1 || n * n * n != ppc || n > 10)
    Options::bad(p + "ppc", std::to_string(ppc), "must be a perfect cube n^3 with 1 <= n <= 10");
  b.ppc = static_cast<int>(ppc);
  const int nh = static_cast<int>(std::lround(std::cbrt(static_cast<double>(hppc))));
  if (hppc != 0 && (hppc < 1 || nh * nh * nh != hppc || nh > 10))
    Options::bad(p + "hole_ppc", std::to_string(hppc),
                 "must be 0 or a perfect cube n^3 with 1 <= n <= 10");
  b.holePpc = static_cast<int>(hppc ? hppc : ppc);
  if (!vel.empty()) std::copy(vel.begin(), vel.end(), b.velocity.begin());
  if (!spin.empty()) std::copy(spin.begin(), spin.end(), b.spin.begin());
  o.needs(b.sineProfile, p + "wavenumber", "-" + p + "velocity_profile sine_x");
  if (b.sineProfile && !(b.wavenumber > 0))
    Options::bad(p + "wavenumber", formatNumber(b.wavenumber),
                 "must be > 0 [1/m] with the sine profile");
}

} // namespace

void readBodies(const Options &o, Scene<3> &sc) {
  const PetscInt nb = o.integer("gimp_bodies", 1);
  sc.oneMaterial = true;
  for (PetscInt k = 0; k < (o.help() ? 1 : nb); ++k) {
    const std::string p = "gimp_body" + std::to_string(k) + "_";
    Body<3> b;
    readSolid(o, p, b);
    readSolidHoles(o, p, b);
    readSolidMotion(o, p, b);
    readBodyMaterial(o, p, sc.material, sc.sceneE, sc.sceneRho, b.material);
    for (const char *m : {"material", "E", "nu", "rho"})
      if (o.given(p + m)) sc.oneMaterial = false;
    if (!o.help()) sc.bodies.push_back(b);
  }
}

void checkBodies(const Scene<3> &sc) {
  for (size_t k = 0; k < sc.bodies.size(); ++k)
    checkFileParticles<3>(sc, k);
  // Every body inside the grid: nothing of a body is dropped at the domain's faces.
  for (size_t k = 0; k < sc.bodies.size(); ++k) {
    const BoxOf<3> &b = sc.bodies[k].box;
    for (int a = 0; a < 3; ++a)
      if (b[a] < sc.domain[a] - 1e-9 * sc.h || b[3 + a] > sc.domain[3 + a] + 1e-9 * sc.h)
        Options::bad("gimp_body" + std::to_string(k) + "_" + sc.bodies[k].shapeOption,
                     fmtList(b.data(), 6),
                     "the body (its box " + fmtList(b.data(), 6) +
                         ") must lie inside -gimp_domain " + fmtList(sc.domain.data(), 6));
  }
}

void domainAroundBodies(Scene<3> &sc) {
  // The bodies' bounding box on the grid lines through the origin, padded by pad cells.
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

} // namespace gimp::input

namespace gimp {

std::string approximateCuts(const Body<3> &b, const std::string &prefix) {
  auto text = [](const Solid &s) {
    return formatNumber(s.c[0]) + "," + formatNumber(s.c[1]) + "," + formatNumber(s.c[2]) + "," +
           formatNumber(s.r);
  };
  auto distance = [](const Solid &a, const Solid &c) {
    return std::sqrt((a.c[0] - c.c[0]) * (a.c[0] - c.c[0]) + (a.c[1] - c.c[1]) * (a.c[1] - c.c[1]) +
                     (a.c[2] - c.c[2]) * (a.c[2] - c.c[2]));
  };
  for (size_t i = 0; i < b.holes.size(); ++i) {
    const Solid &h = b.holes[i];
    if (h.kind != Solid::Sphere) continue;
    if (b.kind == Body<3>::RoundShape && b.round.kind == Solid::Sphere) {
      const double d = distance(h, b.round);
      if (d < b.round.r + h.r && d > b.round.r - h.r)
        return "-" + prefix + "hole_spheres " + text(h) + ": the hole crosses the surface of " +
               "-" + prefix + "sphere " + text(b.round);
    }
    for (size_t j = i + 1; j < b.holes.size(); ++j)
      if (b.holes[j].kind == Solid::Sphere && distance(h, b.holes[j]) < h.r + b.holes[j].r)
        return "-" + prefix + "hole_spheres " + text(h) + " and " + text(b.holes[j]) +
               ": the two holes meet";
  }
  return "";
}

} // namespace gimp
