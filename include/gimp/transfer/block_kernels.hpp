// The 2D kernels of a block particle (grid/stencils.hpp, Block<2, N>) in tensor-product form:
// sums along x for each row of nodes, then along y; a node's x and y values as one SSE2 pair
// (core/pair.hpp). N = 3 for half-sizes up to h/2, N = 4 up to h. The rows along y stop at the
// last one the particle reaches (rowsReached); along x all N nodes are summed (the ones it does
// not reach have weight and slope 0). The kernels of transfer.hpp, affine.hpp and
// transfer/internal_force.hpp call these for their block particles.
#pragma once

#include "gimp/core/pair.hpp"
#include "gimp/core/tensor.hpp"
#include "gimp/grid/stencils.hpp"

namespace gimp::transfer {

/// The inverse of a 2 x 2 inertia (a, b; c, d), or 0 where it is singular (see below).
inline Tensor<2> invertInertia(double a, double b, double c, double d) {
  const double det = a * d - b * c;
  const double half = 0.5 * (a + d);
  if (!(det > 1e-12 * half * half)) return Tensor<2>::Zero();
  const double id = 1.0 / det;
  Tensor<2> r;
  r << d * id, -b * id, -c * id, a * id;
  return r;
}

namespace blocks {

using simd::Pair;

/// The rows of nodes along y to visit: all 3 of a 3-node block (its third may be 0); of a 4-node
/// block those up to the last with a weight or slope (at least 2).
template <int N> GIMP_ALWAYS_INLINE int rowsReached(const Block<2, N> &b) {
  if constexpr (N == 3)
    return 3;
  else
    return Stencils<2>::nodesReached(b, 1);
}

/// sum_i c_i f_i over the N pairs at f, f + 2, ... (in order).
template <int N> GIMP_ALWAYS_INLINE Pair rowSum(const double *c, const double *f) {
  Pair t = c[0] * simd::load(f);
  for (int i = 1; i < N; ++i)
    t += c[i] * simd::load(f + 2 * i);
  return t;
}

/// A block's weights (those along x also as pairs) and the first slot (times 2) of each row of
/// its nodes, read into locals before a kernel's first store: the compiler cannot tell the block
/// from the nodal arrays the kernel writes.
template <int N> struct BlockLocals {
  double wx[N], wy[N];
  Pair w2[N];
  PetscInt row[N];
  GIMP_ALWAYS_INLINE explicit BlockLocals(const Block<2, N> &b) {
    for (int i = 0; i < N; ++i) {
      wx[i] = b.w[0][i];
      wy[i] = b.w[1][i];
      w2[i] = simd::splat(wx[i]);
      row[i] = 2 * (b.base + i * b.stride[0]);
    }
  }
  /// S_ip p2 into mom over the first ny rows and, with mass, S_ip mp into component 0 of mass.
  GIMP_ALWAYS_INLINE void scatter(int ny, Pair p2, double mp, double *mom, double *mass) const {
    for (int j = 0; j < ny; ++j) {
      const double am = wy[j] * mp;
      const Pair a = wy[j] * p2;
      for (int i = 0; i < N; ++i)
        simd::addTo(mom + row[j] + 2 * i, w2[i] * a);
      if (mass)
        for (int i = 0; i < N; ++i)
          mass[row[j] + 2 * i] += wx[i] * am;
    }
  }
};

/// P2G: S_ip p into mom (p = m_p v_p) and, with mass, S_ip m_p into component 0 of mass.
template <int N>
GIMP_ALWAYS_INLINE void toGrid(const Block<2, N> &b, double mp, const double *pk, double *mom,
                               double *mass) {
  BlockLocals<N>(b).scatter(rowsReached(b), Pair{pk[0], pk[1]}, mp, mom, mass);
}

/// G2P: the grid velocity vp and acceleration ap at the particle.
template <int N>
GIMP_ALWAYS_INLINE void fromGrid(const Block<2, N> &b, const double *vg, const double *ag,
                                 double *vp, double *ap) {
  const int ny = rowsReached(b);
  Pair v = {0, 0}, a = {0, 0};
  for (int j = 0; j < ny; ++j) {
    const PetscInt r = 2 * (b.base + j * b.stride[0]);
    v += b.w[1][j] * rowSum<N>(b.w[0], vg + r);
    a += b.w[1][j] * rowSum<N>(b.w[0], ag + r);
  }
  simd::store(vp, v);
  simd::store(ap, a);
}

/// FLIP/PIC G2P and the re-projection of the new momentum with the same block (no mass): the
/// grid velocity vp and acceleration ap at the particle, vk <- flip (vk + dt ap) + (1 - flip) vp,
/// xk += dt vp, then m_p vk into mom. The block is read once, before the first store.
template <int N>
GIMP_ALWAYS_INLINE void fromAndToGrid(const Block<2, N> &b, const double *vg, const double *ag,
                                      double dt, double flip, double mp, double *vk, double *xk,
                                      double *mom) {
  const BlockLocals<N> L(b);
  double vp[2], ap[2];
  fromGrid(b, vg, ag, vp, ap);
  const Pair v = simd::load(vp);
  const Pair vn = flip * (simd::load(vk) + dt * simd::load(ap)) + (1.0 - flip) * v;
  simd::store(vk, vn);
  simd::store(xk, simd::load(xk) + dt * v);
  L.scatter(rowsReached(b), mp * vn, mp, mom, nullptr);
}

/// The nodal field f at the particle.
template <int N>
GIMP_ALWAYS_INLINE void interpolate(const Block<2, N> &b, const double *fg, double *fp) {
  const int ny = rowsReached(b);
  Pair f = {0, 0};
  for (int j = 0; j < ny; ++j)
    f += b.w[1][j] * rowSum<N>(b.w[0], fg + 2 * (b.base + j * b.stride[0]));
  simd::store(fp, f);
}

/// L = sum_i v_i (x) grad S_ip: L(c, 0) = sum_j w_j sum_i g_i v_c, L(c, 1) = sum_j g_j sum_i w_i
/// v_c (both components c at once).
template <int N> GIMP_ALWAYS_INLINE Tensor<2> gradient(const Block<2, N> &b, const double *vg) {
  const int ny = rowsReached(b);
  Pair L0 = {0, 0}, L1 = {0, 0};
  for (int j = 0; j < ny; ++j) {
    const double *r = vg + 2 * (b.base + j * b.stride[0]);
    L0 += b.w[1][j] * rowSum<N>(b.g[0], r);
    L1 += b.g[1][j] * rowSum<N>(b.w[0], r);
  }
  Tensor<2> Lk;
  Lk << L0[0], L1[0], L0[1], L1[1];
  return Lk;
}

/// Internal force: f_ij += A (g_i w_j, w_i g_j) with A = -V_p sigma_p.
template <int N>
GIMP_ALWAYS_INLINE void internalForce(const Block<2, N> &b, const Tensor<2> &A, double *f) {
  // Everything read before the first store (which the compiler cannot tell from the block).
  const int ny = rowsReached(b);
  const Pair A0 = {A(0, 0), A(1, 0)}, A1 = {A(0, 1), A(1, 1)};
  Pair gx[N], wx[N], a[N], c[N];
  PetscInt row[N];
  for (int i = 0; i < N; ++i) {
    gx[i] = simd::splat(b.g[0][i]);
    wx[i] = simd::splat(b.w[0][i]);
    a[i] = A0 * b.w[1][i];
    c[i] = A1 * b.g[1][i];
    row[i] = 2 * (b.base + i * b.stride[0]);
  }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < N; ++i)
      simd::addTo(f + row[j] + 2 * i, gx[i] * a[j] + wx[i] * c[j]);
}

/// The offsets of a block's node lines from the particle xk: dx along x, dy along y for the rows
/// it reaches (xs: slot coordinates).
template <int N>
GIMP_ALWAYS_INLINE void offsets(const Block<2, N> &b, const double *xk, const double *xs,
                                double *dx, double *dy) {
  for (int i = 0; i < N; ++i)
    dx[i] = xs[2 * (b.base + i)] - xk[0];
  for (int j = 0; j < rowsReached(b); ++j)
    dy[j] = xs[2 * (b.base + j * b.stride[0]) + 1] - xk[1];
}

/// The offsets of a block's node lines from the particle xk (as offsets()) and the inverse of
/// its inertia D from the 1D moments of each axis,
/// D = (Sx2 Sy0, Sx1 Sy1; Sx1 Sy1, Sx0 Sy2) with Sa_m = sum_i w_i d_i^m.
template <int N>
GIMP_ALWAYS_INLINE Tensor<2> offsetsAndInverseInertia(const Block<2, N> &b, const double *xk,
                                                      const double *xs, double *dx, double *dy) {
  if constexpr (N == 3) { // both axes at once, each lane in the scalar order
    const Pair xp = {xk[0], xk[1]};
    Pair S0 = {0, 0}, S1 = {0, 0}, S2 = {0, 0};
    for (int i = 0; i < 3; ++i) {
      const Pair d = Pair{xs[2 * (b.base + i)], xs[2 * (b.base + i * b.stride[0]) + 1]} - xp;
      const Pair W = {b.w[0][i], b.w[1][i]};
      dx[i] = d[0];
      dy[i] = d[1];
      const Pair t = W * d;
      S0 += W;
      S1 += t;
      S2 += t * d;
    }
    const Pair a = S2 * Pair{S0[1], S0[0]}; // (Sx2 Sy0, Sy2 Sx0)
    const double dxy = S1[0] * S1[1];
    return invertInertia(a[0], dxy, dxy, S0[0] * S2[1]);
  } else {
    offsets(b, xk, xs, dx, dy);
    double Sx[3] = {0, 0, 0}, Sy[3] = {0, 0, 0};
    for (int i = 0; i < N; ++i) {
      Sx[0] += b.w[0][i];
      Sx[1] += b.w[0][i] * dx[i];
      Sx[2] += b.w[0][i] * dx[i] * dx[i];
    }
    for (int j = 0; j < rowsReached(b); ++j) {
      Sy[0] += b.w[1][j];
      Sy[1] += b.w[1][j] * dy[j];
      Sy[2] += b.w[1][j] * dy[j] * dy[j];
    }
    const double dxy = Sx[1] * Sy[1];
    return invertInertia(Sx[2] * Sy[0], dxy, dxy, Sx[0] * Sy[2]);
  }
}

/// APIC P2G of the affine velocity C about the particle (dx, dy from offsetsAndInverseInertia):
/// the momentum of node (i, j) m w_j [w_i (v + C e_y dy_j) + w_i dx_i C e_x] into mom and, with
/// mass, m w_i w_j into component 0 of mass.
template <int N>
GIMP_ALWAYS_INLINE void affineScatter(const Block<2, N> &b, double mp, const double *vk,
                                      const Tensor<2> &Ck, const double *dx, const double *dy,
                                      double *mom, double *mass) {
  const int ny = rowsReached(b);
  const Pair v = {vk[0], vk[1]}, C0 = {Ck(0, 0), Ck(1, 0)}, C1 = {Ck(0, 1), Ck(1, 1)};
  const BlockLocals<N> L(b);
  Pair wdx[N];
  for (int i = 0; i < N; ++i)
    wdx[i] = simd::splat(L.wx[i] * dx[i]);
  for (int j = 0; j < ny; ++j) {
    const double mw = mp * L.wy[j];
    const Pair r = mw * (v + C1 * dy[j]), t = mw * C0;
    for (int i = 0; i < N; ++i)
      simd::addTo(mom + L.row[j] + 2 * i, L.w2[i] * r + wdx[i] * t);
    if (mass)
      for (int i = 0; i < N; ++i)
        mass[L.row[j] + 2 * i] += L.wx[i] * mw;
  }
}

/// APIC P2G with C = B D^-1 formed from the block (xs: slot coordinates).
template <int N>
GIMP_ALWAYS_INLINE void affineToGrid(const Block<2, N> &b, double mp, const double *vk,
                                     const Tensor<2> &Bk, const double *xk, const double *xs,
                                     double *mom, double *mass) {
  double dx[N], dy[N];
  const Tensor<2> Ck = product<2>(Bk, offsetsAndInverseInertia(b, xk, xs, dx, dy));
  affineScatter(b, mp, vk, Ck, dx, dy, mom, mass);
}

/// APIC G2P with the offsets dx, dy of the node lines: v_p = sum S v and
/// B_p = sum S v (x_i - x_p)^T.
template <int N>
GIMP_ALWAYS_INLINE void affineGather(const Block<2, N> &b, const double *vg, const double *dx,
                                     const double *dy, double *vp, Tensor<2> &Bk) {
  const int ny = rowsReached(b);
  Pair v = {0, 0}, B0 = {0, 0}, B1 = {0, 0};
  for (int j = 0; j < ny; ++j) {
    const PetscInt r = 2 * (b.base + j * b.stride[0]);
    Pair wv[N];
    for (int i = 0; i < N; ++i)
      wv[i] = b.w[0][i] * simd::load(vg + r + 2 * i);
    Pair t = wv[0], u = wv[0] * dx[0];
    for (int i = 1; i < N; ++i) {
      t += wv[i];
      u += wv[i] * dx[i];
    }
    v += b.w[1][j] * t;
    B0 += b.w[1][j] * u;
    B1 += b.w[1][j] * dy[j] * t;
  }
  simd::store(vp, v);
  Bk << B0[0], B1[0], B0[1], B1[1];
}

/// APIC G2P: v_p = sum S v and B_p = sum S v (x_i - x_p)^T about xk.
template <int N>
GIMP_ALWAYS_INLINE void affineFromGrid(const Block<2, N> &b, const double *vg, const double *xk,
                                       const double *xs, double *vp, Tensor<2> &Bk) {
  double dx[N], dy[N];
  offsets(b, xk, xs, dx, dy);
  affineGather(b, vg, dx, dy, vp, Bk);
}

/// APIC G2P and the re-projection of the new v_p, B_p with the same block (no mass): the
/// offsets and D^-1 formed once for both.
template <int N>
GIMP_ALWAYS_INLINE void affineFromAndToGrid(const Block<2, N> &b, double mp, const double *vg,
                                            const double *xk, const double *xs, double *vp,
                                            Tensor<2> &Bk, double *mom) {
  double dx[N], dy[N];
  const Tensor<2> Di = offsetsAndInverseInertia(b, xk, xs, dx, dy);
  affineGather(b, vg, dx, dy, vp, Bk);
  affineScatter(b, mp, vp, product<2>(Bk, Di), dx, dy, mom, nullptr);
}

} // namespace blocks

} // namespace gimp::transfer
