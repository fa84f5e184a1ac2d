// The part of a particle's square that lies in the body when a curved edge (a circular hole)
// cuts it: its area, centroid and central second moments, and the rectangle that stands for it.
// Plain geometry: no PETSc, no grid.
#pragma once

#include <array>
#include <vector>

namespace gimp::cut {

/// Area, first and second moments of a plane region: A, the centroid (cx, cy) and the central
/// second moments Ixx = int (x - cx)^2 dA, Iyy = int (y - cy)^2 dA.
struct Moments {
  double A = 0, cx = 0, cy = 0, Ixx = 0, Iyy = 0;
};

/// Raw moments int {1, x, y, x^2, y^2} dA of the intersection of the rectangle
/// [x0, x1] x [y0, y1] with the disk of centre (ox, oy) and radius r. Exact up to round-off:
/// the region is integrated over x = ox + r sin(theta), split where its top or bottom changes
/// from the circle to the rectangle, so each piece is analytic in theta and a 16-point
/// Gauss-Legendre rule integrates it to machine precision.
std::array<double, 5> rectDiskMoments(double x0, double y0, double x1, double y1, double ox,
                                      double oy, double r);

/// The raw moments {A, Sx, Sy, Sxx, Syy} of a w x h rectangle about its centre.
inline std::array<double, 5> centredRectangleMoments(double w, double h) {
  return {w * h, 0.0, 0.0, w * h * w * w / 12.0, w * h * h * h / 12.0};
}

/// The moments of the rectangle [x0, x1] x [y0, y1] minus the disks (ox, oy, r) given as
/// triples (the disks must not overlap inside the rectangle).
Moments rectMinusDisks(double x0, double y0, double x1, double y1,
                       const std::vector<std::array<double, 3>> &disks);

/// The region's moments from its raw moments {A, Sx, Sy, Sxx, Syy} about (xc, yc); an empty
/// region (A = 0) when A is at most 1e-13 of `whole` (the round-off of a removed square).
Moments fromRaw(const std::array<double, 5> &mom, double xc, double yc, double whole);

/// The rectangle standing for a cut region in GIMP's weights: centred on the centroid, with
/// the aspect ratio of the region's central second moments (a rectangle of half-sizes a, b has
/// Ixx / Iyy = a^2 / b^2), scaled to the region's area. Half-sizes into l[0], l[1].
void equivalentRectangle(const Moments &m, double l[2]);

/// The smallest half-size of a cut particle's domain along each axis, as a fraction of the
/// square's (src/particles/seed.cpp).
constexpr double kMinSliverFraction = 0.25;

} // namespace gimp::cut
