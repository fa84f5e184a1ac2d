// The scene's types: load tables, materials, the bodies' shapes (2D plane bodies, 3D solids)
// and what the scene answers about them.
#include "gimp/input/scene.hpp"

#include <algorithm>
#include <cmath>

namespace gimp {

double Ramp::at(double time) const {
  if (t.empty()) return 1.0;
  if (time <= t.front()) return f.front();
  for (size_t k = 1; k < t.size(); ++k)
    if (time <= t[k]) return f[k - 1] + (f[k] - f[k - 1]) * (time - t[k - 1]) / (t[k] - t[k - 1]);
  return f.back();
}

bool Body<2>::inUnion(double x, double y) const {
  if (shape.contains(x, y)) return true;
  for (const Shape &s : added)
    if (s.contains(x, y)) return true;
  return false;
}

bool Body<2>::strictlyInUnion(double x, double y) const {
  if (shape.strictlyInside(x, y)) return true;
  for (const Shape &s : added)
    if (s.strictlyInside(x, y)) return true;
  return false;
}

std::vector<const Shape *> Body<2>::parts() const {
  std::vector<const Shape *> all = {&shape};
  for (const Shape &s : added)
    all.push_back(&s);
  return all;
}

std::array<double, 5> Body<2>::unionMomentsIn(double x0, double y0, double x1, double y1, double ox,
                                              double oy) const {
  const std::vector<const Shape *> all = parts();
  std::array<double, 5> m{};
  for (const Shape *s : all) {
    const auto a = s->momentsIn(x0, y0, x1, y1, ox, oy);
    for (int k = 0; k < 5; ++k)
      m[k] += a[k];
  }
  for (size_t i = 0; i < all.size(); ++i)
    for (size_t j = i + 1; j < all.size(); ++j) {
      const Shape &a = *all[i], &b = *all[j];
      if (a.box[0] >= b.box[2] || b.box[0] >= a.box[2] || a.box[1] >= b.box[3] ||
          b.box[1] >= a.box[3] || !intersectable(a, b))
        continue; // apart (a pair that overlaps is intersectable: checked at input)
      const auto ab = intersectionMomentsIn(a, b, x0, y0, x1, y1, ox, oy);
      for (int k = 0; k < 5; ++k)
        m[k] -= ab[k];
    }
  return m;
}

std::vector<std::array<double, 2>> Body<2>::boundaryPoints(int perShape) const {
  std::vector<std::array<double, 2>> pts;
  for (const Shape *s : parts()) {
    const auto more = s->boundaryPoints(perShape);
    pts.insert(pts.end(), more.begin(), more.end());
  }
  return pts;
}

bool Body<2>::inside(double x, double y) const {
  if (!inUnion(x, y)) return false;
  for (const Hole &c : holes)
    if ((x - c.cx) * (x - c.cx) + (y - c.cy) * (y - c.cy) < c.r * c.r) return false;
  for (const Shape &h : shapeHoles)
    if (h.strictlyInside(x, y)) return false;
  return true;
}

bool Body<2>::strictlyInside(double x, double y) const {
  if (!strictlyInUnion(x, y)) return false;
  for (const Hole &c : holes)
    if ((x - c.cx) * (x - c.cx) + (y - c.cy) * (y - c.cy) <= c.r * c.r) return false;
  for (const Shape &h : shapeHoles)
    if (h.contains(x, y)) return false;
  return true;
}

bool bodiesOverlap(const Body<2> &a, const Body<2> &b) {
  // A body from a particle file: its particles' centres strictly inside the other body (two
  // file bodies are taken as given).
  if (!a.file.empty() || !b.file.empty()) {
    if (!a.file.empty() && !b.file.empty()) return false;
    const Body<2> &f = a.file.empty() ? b : a, &o = a.file.empty() ? a : b;
    for (const FileParticle<2> &p : f.fromFile.particles)
      if (o.strictlyInside(p.x[0], p.x[1])) return true;
    return false;
  }
  return interiorsMeet(
      a.box, b.box, [&] { return a.boundaryPoints(720); }, [&] { return b.boundaryPoints(720); },
      [&](double x, double y) { return a.strictlyInside(x, y); },
      [&](double x, double y) { return b.strictlyInside(x, y); });
}

template <int D> double Scene<D>::cellSizeAt(const double *x) const {
  double hk = this->h, at = this->h;
  for (size_t k = 0; k < this->levels.size(); ++k) {
    const BoxOf<D> &b = this->levels[k].box;
    hk /= k ? this->levels[k].ratio : 1;
    bool in = true;
    for (int a = 0; a < D; ++a)
      in = in && x[a] >= b[a] && x[a] <= b[D + a];
    if (in) at = hk;
  }
  return at;
}

template <int D> const Material &Scene<D>::materialAt(const double *x) const {
  for (const Body<D> &b : bodies)
    if (b.inside(x)) return b.material;
  return material;
}

template <int D> double Scene<D>::maxWaveSpeed() const {
  if (oneMaterial || bodies.empty()) return material.waveSpeed();
  double c = 0; // every body carries its material (the scene's unless it sets its own)
  for (const Body<D> &b : bodies)
    c = std::max(c, b.material.waveSpeed());
  return c;
}

double Material::lambdaEff() const {
  return planeStrain ? lambda : 2.0 * mu * lambda / (lambda + 2.0 * mu);
}

double Material::waveSpeed() const {
  return std::sqrt((lambdaEff() + 2.0 * mu) / rho);
}

template <int D> bool Scene<D>::hasExternalForces() const {
  bool gravity = false;
  for (double g : this->gravity)
    gravity = gravity || g != 0;
  return !this->tractions.empty() || !this->dbcs.empty() || gravity || mms != Mms::None;
}

bool Solid::contains(const double *x) const {
  if (kind == Sphere) {
    double d2 = 0;
    for (int a = 0; a < 3; ++a)
      d2 += (x[a] - c[a]) * (x[a] - c[a]);
    return d2 <= r * r;
  }
  if (x[axis] < lo || x[axis] > hi) return false;
  double d2 = 0;
  for (int a = 0; a < 3; ++a)
    if (a != axis) d2 += (x[a] - c[a]) * (x[a] - c[a]);
  return d2 <= r * r;
}

bool Solid::strictlyContains(const double *x) const {
  double d2 = 0;
  for (int a = 0; a < 3; ++a) {
    if (kind == BoxHole && !(x[a] > b[a] && x[a] < b[3 + a])) return false;
    if (kind == Sphere || (kind == Cylinder && a != axis)) d2 += (x[a] - c[a]) * (x[a] - c[a]);
  }
  return kind == BoxHole || d2 < r * r;
}

BoxOf<3> Solid::box() const {
  BoxOf<3> bb;
  for (int a = 0; a < 3; ++a) {
    const bool along = kind == Cylinder && a == axis;
    bb[a] = along ? lo : c[a] - r;
    bb[3 + a] = along ? hi : c[a] + r;
  }
  return bb;
}

bool Body<3>::inside(const double *x) const {
  for (int a = 0; a < 3; ++a)
    if (x[a] < box[a] || x[a] > box[3 + a]) return false;
  if (kind == RoundShape && !round.contains(x)) return false;
  for (const Solid &h : holes) // open: a hole's boundary belongs to the body
    if (h.strictlyContains(x)) return false;
  return true;
}

template <> double Traction<3>::loadedArea(double a0, double a1, double b0, double b1) const {
  if (!hasDisk) return (a1 - a0) * (b1 - b0);
  return Shape::ellipse(disk[0], disk[1], disk[2], disk[2]).momentsIn(a0, b0, a1, b1, 0, 0)[0];
}

template struct Scene<2>;
template struct Scene<3>;

} // namespace gimp
