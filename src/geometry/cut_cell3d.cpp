// Moments of a box cut by a sphere or a cylinder (see include/gimp/geometry/cut_cell3d.hpp).
#include "gimp/geometry/cut_cell3d.hpp"

#include "gimp/geometry/cut_cell.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gimp::cut {

namespace {

// 8-point Gauss-Legendre nodes and weights on [-1, 1] (the positive half).
constexpr double kX[4] = {0.1834346424956498, 0.525532409916329, 0.7966664774136267,
                          0.9602898564975363};
constexpr double kW[4] = {0.362683783378362, 0.3137066458778873, 0.2223810344533745,
                          0.1012285362903763};

/// The slice of the box [lo, hi] (x, y) at height z through the ball: {A, Sx, Sy, Sxx, Syy}.
using Slice = std::array<double, 5>;

struct BallSlicer {
  const double *lo, *hi, *o;
  double r;
  Slice at(double z) const {
    const double rho2 = r * r - (z - o[2]) * (z - o[2]);
    if (rho2 <= 0) return Slice{};
    return rectDiskMoments(lo[0], lo[1], hi[0], hi[1], o[0], o[1], std::sqrt(rho2));
  }
  /// The 8-point rule's moments of the slices over [a, b] (raw moments, z weighted in).
  Raw3 rule(double a, double b) const {
    Raw3 m{};
    const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
    for (int q = 0; q < 8; ++q) {
      const double z = mid + (q < 4 ? -kX[q] : kX[q - 4]) * half, w = kW[q % 4] * half;
      const Slice s = at(z);
      const double add[7] = {s[0], s[1], s[2], z * s[0], s[3], s[4], z * z * s[0]};
      for (int i = 0; i < 7; ++i)
        m[i] += w * add[i];
    }
    return m;
  }
  /// Adaptive bisection: [a, b] whose rule `whole` agrees with its halves' sum to tol[i].
  void adapt(double a, double b, const Raw3 &whole, const Raw3 &tol, int depth, Raw3 &m) const {
    const double mid = 0.5 * (a + b);
    const Raw3 left = rule(a, mid), right = rule(mid, b);
    bool ok = true;
    for (int i = 0; i < 7; ++i)
      ok = ok && std::fabs(left[i] + right[i] - whole[i]) <= tol[i];
    if (ok || depth >= 40) {
      for (int i = 0; i < 7; ++i)
        m[i] += left[i] + right[i];
      return;
    }
    Raw3 half = tol;
    for (double &t : half)
      t *= 0.5;
    adapt(a, mid, left, half, depth + 1, m);
    adapt(mid, b, right, half, depth + 1, m);
  }
};

} // namespace

Raw3 centredBoxMoments(const double w[3]) {
  const double V = w[0] * w[1] * w[2];
  return {V, 0, 0, 0, V * w[0] * w[0] / 12.0, V * w[1] * w[1] / 12.0, V * w[2] * w[2] / 12.0};
}

Raw3 boxBallMoments(const double lo[3], const double hi[3], const double o[3], double r) {
  Raw3 m{};
  const double za = std::max(lo[2], o[2] - r), zb = std::min(hi[2], o[2] + r);
  if (zb <= za) return m;
  // Heights where the slice's disk (radius rho) reaches a side (rho = |d|) or a corner.
  std::vector<double> cuts = {za, zb};
  std::vector<double> d2;
  for (double dx : {lo[0] - o[0], hi[0] - o[0]}) {
    d2.push_back(dx * dx);
    for (double dy : {lo[1] - o[1], hi[1] - o[1]})
      d2.push_back(dx * dx + dy * dy);
  }
  for (double dy : {lo[1] - o[1], hi[1] - o[1]})
    d2.push_back(dy * dy);
  for (double d : d2) {
    if (d >= r * r) continue;
    const double t = std::sqrt(r * r - d);
    for (double z : {o[2] - t, o[2] + t})
      if (z > za && z < zb) cuts.push_back(z);
  }
  std::sort(cuts.begin(), cuts.end());
  // Tolerances: 1e-15 of the moments of a box of the slab's size about the box's corner scale.
  double s = 0;
  for (int a = 0; a < 3; ++a)
    s = std::max({s, std::fabs(lo[a]), std::fabs(hi[a]), hi[a] - lo[a]});
  const double V = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]) * 1e-15;
  const Raw3 tol = {V, V * s, V * s, V * s, V * s * s, V * s * s, V * s * s};
  const BallSlicer slicer{lo, hi, o, r};
  for (size_t i = 0; i + 1 < cuts.size(); ++i)
    if (cuts[i + 1] > cuts[i])
      slicer.adapt(cuts[i], cuts[i + 1], slicer.rule(cuts[i], cuts[i + 1]), tol, 0, m);
  return m;
}

Raw3 boxCylinderMoments(const double lo[3], const double hi[3], int axis, const double o[3],
                        double r, double zlo, double zhi) {
  Raw3 m{};
  const double za = std::max(lo[axis], zlo), zb = std::min(hi[axis], zhi);
  if (zb <= za) return m;
  const int a = axis == 0 ? 1 : 0, b = axis == 2 ? 1 : 2; // the disk's plane, in order
  const Slice s = rectDiskMoments(lo[a], lo[b], hi[a], hi[b], o[a], o[b], r);
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
