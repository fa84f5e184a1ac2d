// Explicit cracks: a crack is an open polyline, and the questions the grid asks of it. No PETSc,
// no grid: plain 2D geometry, cheap enough to ask per stencil entry near a crack.
//
// Orientation. Segment k runs from points[k] to points[k + 1] with direction t; its normal
// n = (-t_y, t_x) / |t| points to its *left* side. A point x is on the left of segment k when
// cross(t, x - points[k]) > 0.
//
// What crossing() answers is exact for a perturbed crack: the crack moved by an infinitesimal
// distance to its right (each segment parallel to itself, the vertices mitred) and shortened
// infinitesimally at both ends. No point then lies on the crack, no segment passes through a
// vertex, and the answer is topological.
//
// Tolerance. "On a line" means an orientation test cross(q - p, x - p) within delta |q - p|, i.e.
// x within delta of the line through p, q. Testing a, b against a crack segment pq,
// delta = kCrackTol (|ab| + |pq|); testing a crack vertex v against the line ab,
// delta = kCrackTol (|ab| + |v - c|), c the lexicographically smaller of a and b (a property
// of v alone, so both segments at v see it alike); |pq| and |v - c| are taken in the 1-norm
// |dx| + |dy|. The points a test compares are within about |ab| + |pq| (or |v - c|) of each
// other after the bounding-box rejection, so the rounding error of that distance is a few machine
// epsilons times the same length, far below delta; and delta is far below any length the
// method resolves. Points within delta count as exactly on the line.
#pragma once

#include <array>
#include <vector>

namespace gimp {

/// An open polyline crack. tip[0]: the first point is a crack tip (inside a body), tip[1]: the
/// last one; an end that is not a tip is a mouth (on or outside a body's edge).
struct Crack {
  std::vector<std::array<double, 2>> points;
  bool tip[2] = {false, false};
  int grown[2] = {0, 0}; // points added at each end by crack growth (the first and last ones)
};

namespace cracks {

/// Relative tolerance of the orientation tests (see the file comment).
constexpr double kCrackTol = 1e-9;

/// Whether the segment a->b crosses the crack, and from which side: 0 if it does not, +1 if a is
/// on the left of the crossed crack segment, -1 if on the right. As for the perturbed crack of
/// the file comment, that is:
///  - a point on the crack (within delta of a segment's line) is on its LEFT side: a segment from
///    the right that ends on the crack crosses (-1; +1 for the reverse), one from the left, or
///    one along the crack line, does not;
///  - the two end points (tip or mouth) are not part of the crack: a segment that passes through
///    an end point, beyond it, or ends at it, does not cross there;
///  - a segment through an interior vertex crosses once if it passes from one side of the crack
///    to the other there, and not at all if it only touches a kink (an end at the vertex is on
///    the left of both segments there);
///  - crossings count with parity: an even number (a segment through both arms of a kink) is no
///    crossing; for an odd number the side is a's relative to the crossed segment nearest to a;
///  - a == b never crosses. With one crossing, crossing(a, b) == -crossing(b, a).
int crossing(const Crack &c, double ax, double ay, double bx, double by);

/// The segments of c (in increasing order) whose bounding box comes within a millionth of the
/// box's and the segment's sizes of the box x0, y0, x1, y1: the only ones crossing() can count for
/// a segment a-b inside that box (it tests each segment's box with a margin of kCrackTol times
/// such sizes).
void segmentsNear(const Crack &c, const double box[4], std::vector<int> &out);

/// crossing() over the segments `segs` alone (segmentsNear of a box that holds a and b): the same
/// answer.
int crossing(const Crack &c, const std::vector<int> &segs, double ax, double ay, double bx,
             double by);

/// Distance from (x, y) to the polyline [m].
double distance(const Crack &c, double x, double y);

/// The unit normal (left side) of the crack segment nearest to (x, y), into n; returns that
/// segment's index (ties: the lowest index), or -1 and n = 0 for fewer than two points.
int normalAt(const Crack &c, double x, double y, double n[2]);

/// The side of (x, y) relative to the line of crack segment `seg` as crossing() sees a grid
/// node: +1 left or on the line (within kCrackTol |pq|), -1 right. A node computed on the line
/// with rounding error (a refined level's coordinates) must fall on the side crossing() gives it.
int sideOf(const Crack &c, int seg, double x, double y);

/// Whether the polyline comes within `reach` (>= 0) of the box x0, y0, x1, y1 (the box's
/// interior counts: a crack inside the box is at distance 0).
bool nearCrack(const Crack &c, const double box[4], double reach);

/// Distance between the segments p0-p1 and q0-q1 (0 when they touch or cross).
double segmentDistance(const std::array<double, 2> &p0, const std::array<double, 2> &p1,
                       const std::array<double, 2> &q0, const std::array<double, 2> &q1);

/// Whether the segments p0-p1 and q0-q1 cross or touch, by the orientation tests of the file
/// comment with delta = kCrackTol (|p0p1| + |q0q1|) (1-norm lengths): an end point within delta of
/// the other segment's line, and between its ends, touches it; collinear segments meet when they
/// overlap. Returns 0 when they do not meet, 1 when they touch (an end point on the other
/// segment, or collinear overlap), 2 when they cross properly; `at` is a point where they meet.
int segmentsMeet(const std::array<double, 2> &p0, const std::array<double, 2> &p1,
                 const std::array<double, 2> &q0, const std::array<double, 2> &q1, double at[2]);

/// Where two cracks first meet (segment pairs in order): 0 when they neither cross nor touch,
/// else segmentsMeet's 1 (touch) or 2 (cross) and the point in `at`.
int cracksMeet(const Crack &a, const Crack &b, double at[2]);

/// What is wrong with a polyline as a crack, for the scene's validation: segment i has zero
/// length (<= tol), segments i and i + 1 fold back onto each other (one's far end within tol of
/// the other segment), or non-adjacent segments i < j come within tol of each other.
struct PolylineFault {
  enum Kind { None, ZeroLength, FoldsBack, Intersects } kind = None;
  int i = -1, j = -1;
};
PolylineFault findFault(const Crack &c, double tol);

// The same questions with points as arrays, as the code generic in the dimension asks them of a
// crack of either kind (crack_surface.hpp has the 3D answers).
inline int crossing(const Crack &c, const double *a, const double *b) {
  return crossing(c, a[0], a[1], b[0], b[1]);
}
inline double distance(const Crack &c, const double *x) {
  return distance(c, x[0], x[1]);
}
inline int normalAt(const Crack &c, const double *x, double n[2]) {
  return normalAt(c, x[0], x[1], n);
}
inline int sideOf(const Crack &c, int seg, const double *x) {
  return sideOf(c, seg, x[0], x[1]);
}

} // namespace cracks
} // namespace gimp
