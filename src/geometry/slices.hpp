// The slices of a box integrated along an axis (src/geometry/cut_cell3d.cpp, cut_solids.cpp):
// adaptive Gauss rules over the pieces between the coordinates where a slice changes form.
#pragma once

#include "gimp/geometry/cut_cell3d.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace gimp::cut::slicing {

// 8-point Gauss-Legendre nodes and weights on [-1, 1] (the positive half).
constexpr double kX[4] = {0.1834346424956498, 0.525532409916329, 0.7966664774136267,
                          0.9602898564975363};
constexpr double kW[4] = {0.362683783378362, 0.3137066458778873, 0.2223810344533745,
                          0.1012285362903763};

/// Integrates the density f(t) (the raw moments of the slice at t, t weighted in) over [a, b]
/// split at the cuts, each piece by 8-point Gauss rules bisected until a rule agrees with its
/// halves' sum to tol (the same for every piece: the pieces' round-off, where inclusion-exclusion
/// cancels large terms, falls with their length, so a halved tolerance could fall below it).
template <class F> struct Slices {
  F f;
  Raw3 rule(double a, double b) const {
    Raw3 m{};
    const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
    for (int q = 0; q < 8; ++q) {
      const double t = mid + (q < 4 ? -kX[q] : kX[q - 4]) * half, w = kW[q % 4] * half;
      const Raw3 d = f(t);
      for (int i = 0; i < 7; ++i)
        m[i] += w * d[i];
    }
    return m;
  }
  void adapt(double a, double b, const Raw3 &whole, const Raw3 &tol, int depth, Raw3 &m) const {
    const double mid = 0.5 * (a + b);
    const Raw3 left = rule(a, mid), right = rule(mid, b);
    bool ok = true;
    for (int i = 0; i < 7; ++i)
      ok = ok && std::fabs(left[i] + right[i] - whole[i]) <= tol[i];
    if (ok || depth >= 30) {
      for (int i = 0; i < 7; ++i)
        m[i] += left[i] + right[i];
      return;
    }
    adapt(a, mid, left, tol, depth + 1, m);
    adapt(mid, b, right, tol, depth + 1, m);
  }
  Raw3 over(double a, double b, std::vector<double> cuts, const Raw3 &tol) const {
    Raw3 m{};
    cuts.push_back(a);
    cuts.push_back(b);
    std::sort(cuts.begin(), cuts.end());
    for (size_t i = 0; i + 1 < cuts.size(); ++i) {
      const double lo = std::max(a, cuts[i]), hi = std::min(b, cuts[i + 1]);
      if (hi > lo) adapt(lo, hi, rule(lo, hi), tol, 0, m);
    }
    return m;
  }
};
template <class F> Slices<F> slices(F f) {
  return Slices<F>{f};
}

/// The tolerances of the slices' integration: 1e-15 of the moments of the box about the
/// origin's scale (the callers centre the box near it).
inline Raw3 tolerances(const double lo[3], const double hi[3]) {
  double s = 0;
  for (int a = 0; a < 3; ++a)
    s = std::max({s, std::fabs(lo[a]), std::fabs(hi[a]), hi[a] - lo[a]});
  const double V = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]) * 1e-15;
  return {V, V * s, V * s, V * s, V * s * s, V * s * s, V * s * s};
}

/// The 3D raw moments density of a slice at t along axis sa from its plane moments
/// {A, Sp, Sq, Spp, Sqq} (in-plane axes pa < qa).
inline Raw3 lift(const std::array<double, 5> &s, int sa, int pa, int qa, double t) {
  Raw3 d{s[0]};
  d[1 + pa] = s[1];
  d[1 + qa] = s[2];
  d[1 + sa] = t * s[0];
  d[4 + pa] = s[3];
  d[4 + qa] = s[4];
  d[4 + sa] = t * t * s[0];
  return d;
}

} // namespace gimp::cut::slicing
