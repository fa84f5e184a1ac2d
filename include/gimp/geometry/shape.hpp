// Plane shapes that bodies and their holes are made of: rectangles, axis-aligned ellipses
// (circles) and simple polygons. Each answers whether a point is inside and gives the exact
// moments of its intersection with an axis-aligned rectangle (a particle's square), from which
// seeding takes a cut particle's volume, centroid and domain. Plain geometry: no PETSc, no grid.
#pragma once

#include <algorithm>
#include <array>
#include <string>
#include <vector>

namespace gimp {

struct Shape {
  enum class Kind { Rectangle, Ellipse, Polygon };
  Kind kind = Kind::Rectangle;
  std::array<double, 4> box{}; // Rectangle: x0, y0, x1, y1; every kind: the bounding box
  double cx = 0, cy = 0;       // Ellipse: centre
  double a = 0, b = 0;         // Ellipse: half-axes along x and y (a circle: a = b)
  std::vector<double> xy;      // Polygon: vertices x0, y0, x1, y1, ... counter-clockwise

  static Shape rectangle(double x0, double y0, double x1, double y1);
  static Shape ellipse(double cx, double cy, double a, double b);
  /// Vertices in either orientation (stored counter-clockwise); see polygonProblem.
  static Shape polygon(const std::vector<double> &xy);

  /// Strictly inside, or on the boundary (points on it count as inside).
  bool contains(double x, double y) const;

  /// The raw moments {A, Sx, Sy, Sxx, Syy} = int {1, x', y', x'^2, y'^2} dA over the part of the
  /// rectangle [x0, x1] x [y0, y1] inside the shape, with x' = x - ox, y' = y - oy (take o at
  /// the rectangle's centre so that a small rectangle far from the origin loses no digits).
  /// Exact up to round-off for every kind.
  std::array<double, 5> momentsIn(double x0, double y0, double x1, double y1, double ox,
                                  double oy) const;

  /// Inside and farther than round-off (1e-12 of the bounding box) from the boundary.
  bool strictlyInside(double x, double y) const;

  /// Whether the whole shape lies inside `outer` (boundary points may touch it), from 720
  /// points on this boundary and, for a polygon `outer`, its vertices.
  bool insideOf(const Shape &outer) const;
  /// Whether the interiors of the two shapes meet (touching boundaries do not count): a
  /// boundary point of one strictly inside the other, or a point of a 256 x 256 lattice over
  /// the bounding boxes' intersection strictly inside both.
  bool overlaps(const Shape &other) const;
  /// Points on the boundary, about `n` of them, for containment tests.
  std::vector<std::array<double, 2>> boundaryPoints(int n) const;
};

/// Whether the whole of `s` lies inside the union of `parts` (boundary points may touch it): its
/// boundary (720 points) in the union, and no polygon vertex of a part strictly inside `s` (a
/// notch of a non-convex part reaching into it between the samples).
bool insideOfUnion(const Shape &s, const std::vector<const Shape *> &parts);

/// The first point, in lattice order, of the n x n cell centres over `box` for which `pred(x, y)`
/// holds, into at[0], at[1]; false if none does.
template <class Pred>
bool latticeFind(const std::array<double, 4> &box, int n, Pred pred, double at[2]) {
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = box[0] + (i + 0.5) * (box[2] - box[0]) / n;
      const double y = box[1] + (j + 0.5) * (box[3] - box[1]) / n;
      if (pred(x, y)) {
        at[0] = x;
        at[1] = y;
        return true;
      }
    }
  return false;
}

/// Whether the interiors of two regions meet (touching boundaries do not count): their bounding
/// boxes overlap and a point on one's boundary (`edgeA()`, `edgeB()`) lies strictly inside the
/// other (`inA`, `inB`), or a point of a 256 x 256 lattice over the boxes' intersection lies
/// strictly inside both (one inside the other). Shapes and bodies (with holes) share it.
template <class EdgeA, class EdgeB, class InA, class InB>
bool interiorsMeet(const std::array<double, 4> &boxA, const std::array<double, 4> &boxB,
                   EdgeA edgeA, EdgeB edgeB, InA inA, InB inB) {
  const std::array<double, 4> both = {std::max(boxA[0], boxB[0]), std::max(boxA[1], boxB[1]),
                                      std::min(boxA[2], boxB[2]), std::min(boxA[3], boxB[3])};
  if (!(both[2] > both[0]) || !(both[3] > both[1])) return false;
  for (const auto &p : edgeA())
    if (inB(p[0], p[1])) return true;
  for (const auto &p : edgeB())
    if (inA(p[0], p[1])) return true;
  double at[2];
  return latticeFind(
      both, 256, [&](double x, double y) { return inA(x, y) && inB(x, y); }, at);
}

/// Whether the moments of the intersection of a and b in a rectangle can be taken exactly: one
/// of them is a rectangle, or both are polygons and one is convex.
bool intersectable(const Shape &a, const Shape &b);

/// The raw moments (as Shape::momentsIn) of the part of the rectangle [x0, x1] x [y0, y1] inside
/// both a and b; intersectable(a, b) must hold.
std::array<double, 5> intersectionMomentsIn(const Shape &a, const Shape &b, double x0, double y0,
                                            double x1, double y1, double ox, double oy);

/// Why the polygon x0, y0, x1, y1, ... is not a simple polygon ("" if it is): fewer than 3
/// vertices, an odd count of numbers, a non-finite value, zero area or crossing edges.
std::string polygonProblem(const std::vector<double> &xy);

} // namespace gimp
