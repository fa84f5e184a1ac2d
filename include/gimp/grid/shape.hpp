// GIMP grid shape functions and particle weights with influence zones.
//
// Paper equations: the tent function of a node with influence zone [L-, L+] is Eq. 14,
// the weight between a particle of half-size l and the node is its average over the
// particle (Eqs. 10, 13, 15). In 2D both are products of the 1D functions (Eq. 11).
// A zone of zero on one side (a node on the domain edge) makes that side empty.
#pragma once

#include "gimp/core/pair.hpp"

#include <algorithm>
#include <cmath>

namespace gimp::shape {

/// Nodal tent function S(s), s = x - x_i, Eq. 14.
inline double tent(double s, double Lm, double Lp) {
  if (s < 0.0) return s > -Lm ? 1.0 + s / Lm : 0.0;
  if (s > 0.0) return s < Lp ? 1.0 - s / Lp : 0.0;
  return 1.0; // at the node, also for a node on the domain's high edge (Lp = 0)
}

/// Integral of the tent over [A, B] (A <= B); the numerator of Eq. 15 times 2l. Written in
/// distances from the ends of the tent's support and as (p - q)(p + q), so a particle that
/// barely overlaps a tent gets a small positive weight, not a cancelled difference.
inline double tentIntegral(double A, double B, double Lm, double Lp) {
  double r = 0.0;
  if (Lm > 0.0) { // left part, u = s + Lm in [0, Lm]
    const double p = std::min(B + Lm, Lm), q = std::max(A + Lm, 0.0);
    if (p > q) r += (p - q) * (p + q) / (2.0 * Lm);
  }
  if (Lp > 0.0) { // right part, u = Lp - s in [0, Lp]
    const double p = std::min(Lp - A, Lp), q = std::max(Lp - B, 0.0);
    if (p > q) r += (p - q) * (p + q) / (2.0 * Lp);
  }
  return r;
}

/// True when the particle [d - l, d + l] overlaps the open support (-Lm, Lp) of the tent: the
/// node belongs to the particle's stencil (its weight may still round to zero).
inline bool overlaps(double d, double l, double Lm, double Lp) {
  return d + l > -Lm && d - l < Lp;
}

/// 1D GIMP weight, Eq. 15: d = x_p - x_i, l = particle half-size.
inline double weight(double d, double l, double Lm, double Lp) {
  return tentIntegral(d - l, d + l, Lm, Lp) / (2.0 * l);
}

/// d/dx_p of the 1D weight: (S(d + l) - S(d - l)) / (2 l), exact. At a node on the domain
/// edge (zone 0 on that side) a particle end that lies on the node up to round-off is put on
/// it, so the value is the one from inside the domain (where particles are) and
/// sum_i grad w_i = 0 holds for a particle whose edge lies on the domain edge.
inline double weightGradient(double d, double l, double Lm, double Lp) {
  const double eps = 1e-9 * l;
  double A = d - l, B = d + l;
  if (Lm == 0.0 && A < 0.0 && A > -eps) A = 0.0;
  if (Lp == 0.0 && B > 0.0 && B < eps) B = 0.0;
  return (tent(B, Lm, Lp) - tent(A, Lm, Lp)) / (2.0 * l);
}

/// Weight and gradient together (one call in the inner loops).
inline void weightAndGradient(double d, double l, double Lm, double Lp, double &w, double &g) {
  w = weight(d, l, Lm, Lp);
  g = weightGradient(d, l, Lm, Lp);
}

/// Weight and gradient for equal zones h on both sides (every node away from level and domain
/// boundaries), with the reciprocals ih = 1/h and i2l = 1/(2l) given: the same values as
/// weightAndGradient(d, l, h, h), without divisions or branches in the hot loop. T is double, or
/// simd::Pair for two axes at once (the same operations in the same order in every lane).
template <class T> inline void weightAndGradientUniform(T d, T l, T h, T ih, T i2l, T &w, T &g) {
  const T zero = simd::broadcast<T>(0.0);
  const T A = d - l, B = d + l;
  const T pl = simd::minOf(h, B + h), ql = simd::maxOf(zero, A + h);
  const T pr = simd::minOf(h, h - A), qr = simd::maxOf(zero, h - B);
  const T left = simd::maxOf(zero, pl - ql) * (pl + ql);
  const T right = simd::maxOf(zero, pr - qr) * (pr + qr);
  w = 0.5 * ih * (left + right) * i2l;
  const T tB = simd::maxOf(zero, 1.0 - simd::abs(B) * ih),
          tA = simd::maxOf(zero, 1.0 - simd::abs(A) * ih);
  g = (tB - tA) * i2l;
}

/// Closed-form weights and gradients of the three nodes i0, i0+1, i0+2 of a regular stretch of
/// grid (zones h) for a particle of half-size l <= h/2 whose left end lies in [x_i0, x_i0 + h):
/// xi = (x_p - x_i0) / h, lam = l / h, i2l = h / (2 l), i2lh = 1 / (2 l). The same values as
/// weightAndGradient on each node, in one pass (the common case of every level's interior).
/// T is double, or simd::Pair for two axes at once (lane a of every argument and result is
/// axis a; the same operations in the same order, so the same values).
template <class T> inline void threeNodeWeights(T xi, T lam, T i2l, T i2lh, T *w, T *g) {
  const T one = simd::broadcast<T>(1.0), zero = simd::broadcast<T>(0.0);
  const T a = xi - lam, b = xi + lam; // particle ends relative to node i0, in cells
  const T bb = simd::minOf(one, b), c = simd::maxOf(zero, b - 1.0);
  const T ua = 1.0 - a, ub = 1.0 - bb;
  w[0] = 0.5 * (ua - ub) * (ua + ub) * i2l;
  w[1] = (0.5 * (bb - a) * (bb + a) + c - 0.5 * c * c) * i2l;
  w[2] = 0.5 * c * c * i2l;
  g[0] = (ub - ua) * i2lh;
  g[1] = (1.0 - simd::abs(b - 1.0) - a) * i2lh;
  g[2] = c * i2lh;
}

/// The same for the four nodes i0 .. i0+3 of a particle of half-size l <= h whose left end lies
/// in [x_i0, x_i0 + h) (so its right end lies before x_i0 + 3h): with Phi the integral of the
/// unit tent T, w_n = (Phi(b - n) - Phi(a - n)) h / (2 l) and g_n = (T(b - n) - T(a - n)) / (2 l)
/// for the particle's ends a, b in cells from node i0. The range of a fixes its side's terms;
/// b - n is clamped to the tent's support. The values of weightAndGradientUniform to round-off.
template <class T> inline void fourNodeWeights(T xi, T lam, T i2l, T i2lh, T *w, T *g) {
  const T one = simd::broadcast<T>(1.0), mone = simd::broadcast<T>(-1.0);
  const T a = xi - lam, b = xi + lam; // a in [0, 1): Phi(a) = 1 - ua^2 / 2, Phi(a - 1) = a^2 / 2
  const T ua = 1.0 - a;
  const T vb = 1.0 - simd::minOf(one, b);         // Phi(b) = 1 - vb^2 / 2
  const T u1 = simd::minOf(one, b - 1.0);         // b - 1 in [-1, 1]
  const T u2 = simd::maxOf(mone, b - 2.0);        // b - 2 in [-1, 1)
  const T u3 = simd::maxOf(mone, b - 3.0) + 1.0;  // Phi(b - 3) = u3^2 / 2
  const T a1 = simd::abs(u1), a2 = simd::abs(u2); // Phi(u) = 1/2 + u - u |u| / 2
  w[0] = 0.5 * (ua - vb) * (ua + vb) * i2l;
  w[1] = (0.5 + u1 - 0.5 * u1 * a1 - 0.5 * a * a) * i2l;
  w[2] = (0.5 + u2 - 0.5 * u2 * a2) * i2l;
  w[3] = 0.5 * u3 * u3 * i2l;
  g[0] = (vb - ua) * i2lh;
  g[1] = (1.0 - a1 - a) * i2lh;
  g[2] = (1.0 - a2) * i2lh;
  g[3] = u3 * i2lh;
}

} // namespace gimp::shape
