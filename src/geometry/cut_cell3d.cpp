// Moments of a box cut by a sphere or a cylinder (see include/gimp/geometry/cut_cell3d.hpp).
#include "gimp/geometry/cut_cell3d.hpp"

#include "gimp/geometry/cut_cell.hpp"
#include "slices.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gimp::cut {

using namespace slicing;

Raw3 centredBoxMoments(const double w[3]) {
  const double V = w[0] * w[1] * w[2];
  return {V, 0, 0, 0, V * w[0] * w[0] / 12.0, V * w[1] * w[1] / 12.0, V * w[2] * w[2] / 12.0};
}

Raw3 boxBallMoments(const double lo[3], const double hi[3], const double o[3], double r) {
  const double za = std::max(lo[2], o[2] - r), zb = std::min(hi[2], o[2] + r);
  if (zb <= za) return Raw3{};
  // Heights where the slice's disk (radius rho) reaches a side (rho = |d|) or a corner.
  std::vector<double> cuts, d2;
  for (double dx : {lo[0] - o[0], hi[0] - o[0]}) {
    d2.push_back(dx * dx);
    for (double dy : {lo[1] - o[1], hi[1] - o[1]})
      d2.push_back(dx * dx + dy * dy);
  }
  for (double dy : {lo[1] - o[1], hi[1] - o[1]})
    d2.push_back(dy * dy);
  for (double d : d2)
    if (d < r * r)
      for (double z : {o[2] - std::sqrt(r * r - d), o[2] + std::sqrt(r * r - d)})
        if (z > za && z < zb) cuts.push_back(z);
  const auto ball = slices([&](double z) {
    const double rho2 = r * r - (z - o[2]) * (z - o[2]);
    if (rho2 <= 0) return Raw3{};
    return lift(rectDiskMoments(lo[0], lo[1], hi[0], hi[1], o[0], o[1], std::sqrt(rho2)), 2, 0, 1,
                z);
  });
  return ball.over(za, zb, cuts, tolerances(lo, hi));
}

Raw3 boxCylinderMoments(const double lo[3], const double hi[3], int axis, const double o[3],
                        double r, double zlo, double zhi) {
  Raw3 m{};
  const double za = std::max(lo[axis], zlo), zb = std::min(hi[axis], zhi);
  if (zb <= za) return m;
  const int a = axis == 0 ? 1 : 0, b = axis == 2 ? 1 : 2; // the disk's plane, in order
  const std::array<double, 5> s = rectDiskMoments(lo[a], lo[b], hi[a], hi[b], o[a], o[b], r);
  const double L = zb - za, Z1 = 0.5 * (zb * zb - za * za), Z2 = (zb * zb * zb - za * za * za) / 3;
  m[0] = s[0] * L;
  m[1 + a] = s[1] * L;
  m[1 + b] = s[2] * L;
  m[1 + axis] = s[0] * Z1;
  m[4 + a] = s[3] * L;
  m[4 + b] = s[4] * L;
  m[4 + axis] = s[0] * Z2;
  return m;
}

Raw3 boxBoxMoments(const double lo[3], const double hi[3], const double blo[3],
                   const double bhi[3]) {
  double a[3], b[3], V = 1;
  for (int k = 0; k < 3; ++k) {
    a[k] = std::max(lo[k], blo[k]);
    b[k] = std::min(hi[k], bhi[k]);
    if (b[k] <= a[k]) return Raw3{};
    V *= b[k] - a[k];
  }
  Raw3 m{V};
  for (int k = 0; k < 3; ++k) {
    m[1 + k] = V * 0.5 * (a[k] + b[k]);
    m[4 + k] = V * (a[k] * a[k] + a[k] * b[k] + b[k] * b[k]) / 3.0;
  }
  return m;
}

Moments3 fromRaw3(const Raw3 &mom, const double xc[3], double whole) {
  Moments3 m;
  if (mom[0] <= 1e-13 * whole) return m;
  m.V = mom[0];
  for (int a = 0; a < 3; ++a) {
    const double d = mom[1 + a] / m.V;
    m.c[a] = xc[a] + d;
    m.I[a] = std::max(0.0, mom[4 + a] - m.V * d * d);
  }
  return m;
}

void equivalentBox(const Moments3 &m, double l[3], const double *side) {
  double a[3];
  for (int k = 0; k < 3; ++k)
    a[k] = std::sqrt(3.0 * m.I[k] / m.V);
  if (!(a[0] > 0) || !(a[1] > 0) || !(a[2] > 0)) { // a degenerate sliver: the cube of its volume
    l[0] = l[1] = l[2] = 0.5 * std::cbrt(m.V);
    return;
  }
  // An axis along which the region fills the cube's side (a cylinder's axis through it: its
  // moments there are the side's) keeps it; the others share the scaling, so a cut extruded
  // through the cube has the 2D rectangle of its cross-section.
  double free = 8.0 * a[0] * a[1] * a[2];
  int scaled = 0;
  bool keep[3];
  for (int k = 0; k < 3; ++k) {
    keep[k] = side != nullptr && std::fabs(a[k] - 0.5 * side[k]) <= 1e-12 * side[k];
    if (!keep[k]) ++scaled;
  }
  const double s = scaled == 0 ? 1.0 : std::pow(m.V / free, 1.0 / scaled);
  for (int k = 0; k < 3; ++k)
    l[k] = keep[k] ? a[k] : s * a[k];
}

} // namespace gimp::cut
