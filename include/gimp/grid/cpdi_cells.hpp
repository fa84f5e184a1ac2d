// The cells of CPDI domains and tracked corners: a particle's 2^D corners, in one order for
// every use (the corners field, the CPDI weights, the faces a traction or penalty acts on).
// 2D: counter-clockwise from (-, -): (-, -), (+, -), (+, +), (-, +). 3D: those four on the
// face z = -, then the same four on z = + (the usual hexahedron order).
#pragma once

namespace gimp::cpdi {

/// The side (-1 or +1) of corner q along axis a.
template <int D> constexpr double cornerSign(int q, int a) {
  constexpr double kQuad[2][4] = {{-1, 1, 1, -1}, {-1, -1, 1, 1}}; // [a][q % 4]
  return a < 2 ? kQuad[a][q % 4] : (q >= 4 ? 1.0 : -1.0);
}

/// The volume of the hexahedron of 8 corners (in cornerSign<3> order) under its trilinear map
/// (exact, 2 x 2 x 2 Gauss points); 0 when the map folds.
double hexVolume(const double *c);

} // namespace gimp::cpdi
