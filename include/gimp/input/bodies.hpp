// The bodies of a scene: a body's shape is true geometry, so it is per dimension. In 2D a body
// is a plane shape (rectangle, ellipse, polygon, their union, holes, or a particle file) whose
// cut particle squares keep their exact area and centroid; in 3D a solid (box, sphere or
// cylinder with box, spherical and cylindrical holes) filled with n^3 particles per cell, whose
// cubes a curved surface cuts keep their exact volume and centroid.
// Everything else of a body (material, particles per cell, initial velocity) is the same idea
// in both and has the same name.
#pragma once

#include "gimp/core/box.hpp"
#include "gimp/geometry/shape.hpp"
#include "gimp/input/material.hpp"
#include "gimp/input/particle_file.hpp"

#include <array>
#include <string>
#include <vector>

namespace gimp {

template <int D> struct Body;

/// A circular hole of a plane body.
struct Hole {
  double cx, cy, r;
};

/// A plane body (D = 2).
template <> struct Body<2> {
  Material material;               // the scene's, unless -gimp_bodyK_E etc. set its own
  Shape shape;                     // rectangle (the default), ellipse (circle) or polygon
  std::string shapeOption = "box"; // the option that gave it: box, circle, ellipse, polygon, file
  BoxOf<2> box{};                  // the shape's bounding box (a rectangle's own box)
  std::vector<Hole> holes;         // circular holes (may cross a rectangle's sides)
  std::vector<Shape> shapeHoles;   // elliptic and polygonal holes (inside the shape)
  std::vector<Shape> added;        // shapes joined to the shape (-gimp_bodyK_add_*): the union
  std::string file;                // shape file: the particle file, and its particles
  ParticleFile<2> fromFile;
  int ppc = 4;              // particles per cell (a perfect square: 1, 4, 9, ...)
  int holePpc = 0;          // particles per cell in cells next to a hole (0: same as ppc)
  double holeBand = 0;      // width of the band next to a hole that gets holePpc [m]
  Coords<2> velocity{};     // initial velocity [m/s]
  bool sineProfile = false; // v = velocity * sin(k (X - x0)) instead of uniform
  double wavenumber = 0;    // k [1/m]
  double spin = 0;          // initial rigid rotation about the box's centre [rad/s]
  /// In the union of the shape and the added shapes (boundaries count as inside).
  bool inUnion(double x, double y) const;
  /// Strictly inside one of the union's shapes.
  bool strictlyInUnion(double x, double y) const;
  /// The raw moments of the part of the rectangle inside the union (Shape::momentsIn):
  /// inclusion-exclusion over the shapes, whose pairwise intersections are exact
  /// (intersectable) and which never overlap three at a time (both checked at input).
  std::array<double, 5> unionMomentsIn(double x0, double y0, double x1, double y1, double ox,
                                       double oy) const;
  /// The union's shapes: the shape, then the added ones.
  std::vector<const Shape *> parts() const;
  /// Points on the boundaries of the union's shapes.
  std::vector<std::array<double, 2>> boundaryPoints(int perShape) const;
  /// In the shape and in no hole (boundaries count as inside the body).
  bool inside(double x, double y) const;
  bool inside(const double *x) const { return inside(x[0], x[1]); }
  /// In the shape, off its boundary, and in no hole (not even on a hole's boundary).
  bool strictlyInside(double x, double y) const;
};

/// Whether two plane bodies share interior (a body inside another's hole does not).
bool bodiesOverlap(const Body<2> &a, const Body<2> &b);

/// A solid a 3D body is made of, or one of its holes: a sphere (centre c, radius r), a cylinder
/// along `axis` (centre c in the other two coordinates, from lo to hi along the axis; a hole's
/// runs through the whole body) or, for a hole, a box.
struct Solid {
  enum Kind { Sphere, Cylinder, BoxHole } kind = Sphere;
  int axis = 2;
  Coords<3> c{};
  double r = 0, lo = -1e300, hi = 1e300;
  BoxOf<3> b{}; // BoxHole: its corners
  /// In the closed solid (a sphere, or a cylinder between lo and hi).
  bool contains(const double *x) const;
  /// Strictly inside (a hole: its surface belongs to the body).
  bool strictlyContains(const double *x) const;
  BoxOf<3> box() const;
};

/// A solid body (D = 3).
template <> struct Body<3> {
  Material material;
  enum Kind { BoxShape, RoundShape } kind = BoxShape;
  std::string shapeOption = "box"; // box, sphere, cylinder or file
  BoxOf<3> box{};                  // the body's box (a round or file body's bounding box)
  std::string file;                // shape file: the particle file, and its particles
  ParticleFile<3> fromFile;
  Solid round; // the sphere or cylinder of a round body
  std::vector<Solid> holes;
  int ppc = 8;         // particles per cell, a perfect cube (1, 8, 27, ...)
  int holePpc = 8;     // particles per cell in cells next to a spherical or cylindrical hole
  double holeBand = 0; // width of the band next to such a hole that gets holePpc [m] (0: a cell)
  Coords<3> velocity{};
  bool sineProfile = false; // v = velocity sin(k (X - x0)) along x
  Coords<3> spin{};         // initial rigid rotation omega about the box's centre [rad/s]
  double wavenumber = 0;
  /// In the shape and in no hole (boundaries count as inside the shape, holes are open).
  bool inside(const double *x) const;
};

/// Where a 3D body's cut cells are not exact (docs/method.md, cut cells in 3D): two spherical
/// surfaces that cross or nest (two spherical holes that meet, or a spherical hole that reaches
/// a sphere body's surface), whose common part a cube cut by both loses twice. The option and
/// the two spheres in words, or "" when every cut is exact. `prefix` is "gimp_bodyK_".
std::string approximateCuts(const Body<3> &b, const std::string &prefix);

} // namespace gimp
