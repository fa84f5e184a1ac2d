// Explicit cracks in 3D: a crack is a planar polygon, and the questions the grid asks of it (the
// 3D counterpart of crack.hpp's polyline). No PETSc, no grid: plain geometry.
//
// Orientation. The polygon's vertices p_0 .. p_{m-1} run counter-clockwise about its unit normal
// n (Newell's normal of the vertices as given); edge i runs from p_i to p_{i+1 mod m}. The side
// of a point x is the sign of n.(x - p_0): +1 is the normal's side (the 2D crack's left).
//
// What crossing() answers is exact for a perturbed crack, as in 2D: the polygon moved by an
// infinitesimal distance against its normal, shrunk infinitesimally at its front edges and grown
// infinitesimally at its mouth edges. A point on the plane is then on the + side; a segment
// through a front edge does not cross, one through a mouth edge does (a grid node on a body's
// surface, where a mouth edge lies, belongs to one side of the crack, not to both).
// "On the plane" means |n.(x - p_0)| within delta = kCrackTol (|ab| + span) for a segment a-b
// (kCrackTol span for a point alone), span the polygon's bounding-box size in the 1-norm;
// "inside the polygon" means farther than delta inside its edges.
//
// The front. An edge is a front edge when it lies inside the material (the crack ends there) and
// a mouth when it lies on or outside a body's surface (the crack opens there); the scene decides
// (input/scene_cracks3d.cpp). A front edge's frame: t along the edge, n the crack's normal, and
// a = t x n, the direction in the crack's plane away from the crack (toward the material ahead).
#pragma once

#include <array>
#include <type_traits>
#include <vector>

namespace gimp {

struct Crack;

/// A planar polygon crack. Make it with cracks::makeSurface (which sets the derived members).
struct CrackSurface {
  std::vector<std::array<double, 3>> points; // vertices, counter-clockwise about normal
  std::vector<char> front;                   // per edge: 1 front (in the material), 0 mouth
  // Derived by makeSurface:
  std::array<double, 3> normal{}, e1{}, e2{}; // unit normal, and in-plane axes (e1 x e2 = n)
  std::array<double, 3> origin{};             // p_0
  std::vector<std::array<double, 2>> uv;      // the vertices in (e1, e2) coordinates
  double span = 0;                            // bounding-box size, 1-norm [m]
  // A quick answer for crossing(): in the plane, points nearer than rIn to `centre` are inside
  // the polygon, points farther than rOut outside (rIn 0 when the centre is not inside).
  std::array<double, 2> centre{};
  double rIn = 0, rOut = 0;
};

/// The crack type of a dimension: a polyline in 2D, a planar polygon in 3D.
template <int D> using CrackOf = std::conditional_t<D == 2, Crack, CrackSurface>;

namespace cracks {

/// The bounding box of a crack's points, lows then highs: a polyline's (D = 2) or a polygon's.
template <int D> std::array<double, 2 * D> bounds(const CrackOf<D> &c) {
  std::array<double, 2 * D> b;
  for (int a = 0; a < D; ++a) {
    b[a] = b[D + a] = c.points[0][a];
    for (const auto &p : c.points) {
      b[a] = p[a] < b[a] ? p[a] : b[a];
      b[D + a] = p[a] > b[D + a] ? p[a] : b[D + a];
    }
  }
  return b;
}

/// The polygon of `points` (in either orientation: reversed if Newell's normal of the given order
/// is not `normalHint`'s side, when a hint is given), its frame, plane coordinates and span. All
/// edges are mouths until the scene classifies them.
CrackSurface makeSurface(const std::vector<std::array<double, 3>> &points,
                         const double *normalHint = nullptr);

/// Signed distance of x from the crack's plane (along the normal) [m].
double planeDistance(const CrackSurface &c, const double x[3]);

/// Whether the segment a->b crosses the (perturbed) crack: 0 if not, +1 if a is on the normal's
/// side, -1 if on the other. crossing(a, b) == -crossing(b, a) when it crosses.
int crossing(const CrackSurface &c, const double a[3], const double b[3]);

/// Distance from x to the polygon (the closed planar region) [m].
double distance(const CrackSurface &c, const double x[3]);

/// The point of the polygon (the closed planar region) nearest to x [m].
std::array<double, 3> nearestPoint(const CrackSurface &c, const double x[3]);

/// Whether x, projected on c's plane, lies inside the polygon farther than tol from every front
/// edge (a point on or beyond the front is not behind it; mouth edges are open to the surface).
bool behindFront(const CrackSurface &c, const double x[3], double tol);

/// The unit normal into n; returns 0 (the polygon's one face).
int normalAt(const CrackSurface &c, const double x[3], double n[3]);

/// The side of x as crossing() sees a grid node: +1 on the normal's side or on the plane (within
/// kCrackTol span), -1 on the other. `seg` is ignored (one face).
int sideOf(const CrackSurface &c, int seg, const double x[3]);

/// Whether the polygon may come within `reach` of the box x0, y0, z0, x1, y1, z1: true whenever
/// it does (a box the crack passes through is at distance 0), and possibly when it comes within
/// reach plus the box's half-diagonal.
bool nearCrack(const CrackSurface &c, const double box[6], double reach);

/// What is wrong with a polygon as a crack: fewer than 3 vertices or no area (Degenerate), edge i
/// shorter than tol (ZeroLength), vertex i off the plane by more than tol (NotPlanar), edges i
/// and j < i meeting other than at a shared vertex (Intersects).
struct SurfaceFault {
  enum Kind { None, Degenerate, ZeroLength, NotPlanar, Intersects } kind = None;
  int i = -1, j = -1;
};
SurfaceFault findFault(const std::vector<std::array<double, 3>> &points, double tol);

/// Whether two crack polygons cross or touch (an edge of one through or on the other, within
/// kCrackTol of their spans); `at` a point where they meet.
bool surfacesMeet(const CrackSurface &a, const CrackSurface &b, double at[3]);

/// A point of a crack front where G and K are measured: the centre of a piece of a front edge.
struct FrontPoint {
  int edge = 0;                   // the front edge it lies on
  std::array<double, 3> x{};      // position [m]
  std::array<double, 3> a{}, n{}; // a: ahead (in the plane, away from the crack); n: normal
  std::array<double, 3> t{};      // along the edge (a, n, t... see frontFrame)
};

/// The front points of a crack: each front edge cut into the fewest equal pieces no longer than
/// `spacing` (> 0), a point at each piece's centre; in edge order.
std::vector<FrontPoint> frontPoints(const CrackSurface &c, double spacing);

/// How many pieces frontPoints cuts a front edge of this length into.
int frontPieces(double length, double spacing);

/// The frame of front edge e: t along it (p_e to p_{e+1}), n the normal, a = t x n.
void frontFrame(const CrackSurface &c, int e, double a[3], double n[3], double t[3]);

} // namespace cracks
} // namespace gimp
