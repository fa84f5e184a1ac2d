// The part of a particle's cube that lies in a solid body when a curved surface (a sphere's or a
// cylinder's, of the body or of a hole) cuts it: its volume, centroid and central second
// moments, and the box that stands for it. The 3D analogue of cut_cell.hpp; plain geometry: no
// PETSc, no grid.
#pragma once

#include <array>
#include <vector>

namespace gimp::cut {

/// Raw moments int {1, x, y, z, x^2, y^2, z^2} dV of a solid region.
using Raw3 = std::array<double, 7>;

/// Volume, centroid c and central second moments I[a] = int (x_a - c_a)^2 dV of a solid region.
struct Moments3 {
  double V = 0, c[3] = {0, 0, 0}, I[3] = {0, 0, 0};
};

/// The raw moments of the w[0] x w[1] x w[2] box about its centre.
Raw3 centredBoxMoments(const double w[3]);

/// Raw moments of the intersection of the box [lo, hi] with the ball of centre o and radius r.
/// The box is sliced along z: each slice is a rectangle cut by a disk, whose moments
/// rectDiskMoments gives exactly; the slices are integrated by adaptive Gauss-Legendre between
/// the heights where the slice changes form (the disk reaching a side or a corner of the
/// rectangle), each piece's rule agreeing with its halves to 1e-15 of the box's moments (the
/// sums over a lattice of boxes are the ball's to 1e-13, test_cut_cell3d).
Raw3 boxBallMoments(const double lo[3], const double hi[3], const double o[3], double r);

/// Raw moments of the intersection of the box [lo, hi] with the cylinder of radius r along
/// `axis` through o (o[axis] ignored), between zlo and zhi along the axis: the rectangle cut by
/// the disk (rectDiskMoments, exact) times the length, in closed form.
Raw3 boxCylinderMoments(const double lo[3], const double hi[3], int axis, const double o[3],
                        double r, double zlo, double zhi);

/// Raw moments of the intersection of the boxes [lo, hi] and [blo, bhi].
Raw3 boxBoxMoments(const double lo[3], const double hi[3], const double blo[3],
                   const double bhi[3]);

/// A ball (centre c, radius r) or a cylinder along `axis` (c[axis] ignored) from lo to hi.
struct Round {
  bool ball = true;
  int axis = 2;
  double c[3] = {0, 0, 0};
  double r = 0, lo = -1e300, hi = 1e300;
};

/// Raw moments of the part of the box [lo, hi] in `body` (null: the whole box) and in none of
/// the holes, where several curved surfaces cut the box (src/geometry/cut_solids.cpp). The box
/// is sliced along an axis along which at most one of them is a disk (a ball, or a cylinder
/// along that axis; a cylinder across the slices is a band, a rectangle); each slice's moments
/// are exact by inclusion-exclusion over the holes (the rectangles intersect to a rectangle,
/// cut by the one disk: rectDiskMoments), so overlapping holes are counted once; the slices are
/// integrated as in boxBallMoments. false (m untouched) when every axis has two disks.
bool boxRoundsMoments(const double lo[3], const double hi[3], const Round *body,
                      const std::vector<Round> &holes, Raw3 &m);

/// The region's moments from its raw moments about the point xc; an empty region (V = 0) when
/// V is at most 1e-13 of `whole` (the round-off of a removed cube).
Moments3 fromRaw3(const Raw3 &mom, const double xc[3], double whole);

/// The box standing for a cut region in GIMP's weights (the 3D equivalentRectangle): centred on
/// the centroid, with the proportions of the region's central second moments (a box of
/// half-sizes l has I[a] = V l_a^2 / 3), scaled to the region's volume. An axis along which
/// the region has the second moment of the whole side of the cube (side: the cube's sides, or
/// null), as a cut extruded along it, keeps that side and the other two take the scaling: a
/// cylinder's cut is the 2D rectangle of its cross-section times the side. Half-sizes into l.
void equivalentBox(const Moments3 &m, double l[3], const double *side = nullptr);

} // namespace gimp::cut
