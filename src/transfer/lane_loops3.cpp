// 3D block particles with their three components in lanes (AVX2): see transfer/lane_loops3.hpp.
// Every lane expression below is the scalar one of the kernel named next to it, in the same order;
// these functions have no FMA target and the build no floating-point contraction, so each lane
// rounds as the scalar code does. Lane 3 of every vector is zero and never stored.
#include "gimp/transfer/lane_loops3.hpp"

#include "gimp/physics/deformation.hpp"
#include "gimp/physics/material.hpp"
#include "gimp/transfer/affine.hpp"
#include "gimp/transfer/internal_force.hpp"
#include "gimp/transfer/transfer.hpp"

#include "gimp/core/lanes.hpp"

namespace gimp::transfer::laneLoops3 {

#if GIMP_HAVE_LANES

namespace {

using lanes::V4;

GIMP_LANES_INLINE V4 splat(double a) {
  return _mm256_set1_pd(a);
}

/// The three doubles at p in lanes 0-2, lane 3 zero.
GIMP_LANES_INLINE V4 load3(const double *p) {
  return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p)), _mm_load_sd(p + 2), 1);
}

/// Lanes 0-2 of v to p (p[3] untouched).
GIMP_LANES_INLINE void store3(double *p, V4 v) {
  _mm_storeu_pd(p, _mm256_castpd256_pd128(v));
  _mm_store_sd(p + 2, _mm256_extractf128_pd(v, 1));
}

/// Column a of a row-major 3 x 3 tensor in lanes 0-2.
template <class T> GIMP_LANES_INLINE V4 column(const T &t, int a) {
  return _mm256_set_pd(0.0, t(2, a), t(1, a), t(0, a));
}

/// Columns c[0..2] back into the row-major tensor t.
template <class T> GIMP_LANES_INLINE void setColumns(const V4 *c, T &t) {
  alignas(32) double a[3][4];
  for (int q = 0; q < 3; ++q)
    _mm256_store_pd(a[q], c[q]);
  for (int r = 0; r < 3; ++r)
    for (int q = 0; q < 3; ++q)
      t(r, q) = a[q][r];
}

/// The number of nodes the block reaches along each axis (Stencils::forEach).
GIMP_LANES_INLINE void reached(const Block<3> &b, int *nn) {
  for (int d = 0; d < 3; ++d)
    nn[d] = b.g[d][2] > 0.0 ? 3 : 2;
}

/// f(slot, weight, gradient) for every row entry of particle k (Stencils::forEach of a particle
/// that keeps rows), in a function the lane lambdas can be inlined into.
template <class F> GIMP_LANES_INLINE void forRows(const Stencils<3> &st, PetscInt k, F &&f) {
  for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e)
    f(st.node[e], st.weight(e), st.gradient(e));
}

/// particleToGridAffineB<3> of a particle that keeps rows: D_p (inertiaAbout, its columns in
/// lanes), C = B D^-1, and each entry's S m (v + C (x_i - x_p)) (particleToGridAffine).
GIMP_LANES_INLINE void affineToGridRows(const Stencils<3> &st, PetscInt k, double mp, V4 V,
                                        const Tensor<3> &Bk, const double *xk, const double *xs,
                                        double *mom, double *mass) {
  const V4 XK = load3(xk);
  V4 Dc[3] = {splat(0.0), splat(0.0), splat(0.0)};
  forRows(st, k, [&](PetscInt nd, double w, const Vector<3> &) GIMP_LANES_LAMBDA {
    const V4 WD = splat(w) * (load3(xs + 3 * nd) - XK);
    for (int b = 0; b < 3; ++b)
      Dc[b] = Dc[b] + WD * splat(xs[3 * nd + b] - xk[b]);
  });
  alignas(32) double Dp[3][4];
  for (int b = 0; b < 3; ++b)
    _mm256_store_pd(Dp[b], Dc[b]); // Dp[b][a] = D_p(a, b)
  const Tensor<3> Ck =
      product<3>(Bk, invertInertia(Dp[0][0], Dp[1][1], Dp[2][2], Dp[1][0], Dp[2][0], Dp[2][1]));
  const V4 C0 = column(Ck, 0), C1 = column(Ck, 1), C2 = column(Ck, 2);
  forRows(st, k, [&](PetscInt nd, double w, const Vector<3> &) GIMP_LANES_LAMBDA {
    const V4 VC = V + C0 * splat(xs[3 * nd] - xk[0]) + C1 * splat(xs[3 * nd + 1] - xk[1]) +
                  C2 * splat(xs[3 * nd + 2] - xk[2]);
    store3(mom + 3 * nd, load3(mom + 3 * nd) + splat(w * mp) * VC);
    if (mass) mass[3 * nd] += w * mp;
  });
}

/// particleFromGridAffine<3> of a particle that keeps rows: v_p and the columns of B_p.
GIMP_LANES_INLINE void affineFromGridRows(const Stencils<3> &st, PetscInt k, const double *vg,
                                          const double *xk, const double *xs, V4 &VP, V4 *Bc) {
  VP = Bc[0] = Bc[1] = Bc[2] = splat(0.0);
  forRows(st, k, [&](PetscInt nd, double w, const Vector<3> &) GIMP_LANES_LAMBDA {
    const V4 WV = splat(w) * load3(vg + 3 * nd);
    VP = VP + WV;
    for (int a = 0; a < 3; ++a)
      Bc[a] = Bc[a] + WV * splat(xs[3 * nd + a] - xk[a]);
  });
}

/// particleToGrid<3> of a particle that keeps rows.
GIMP_LANES_INLINE void toGridRows(const Stencils<3> &st, PetscInt k, double mp, V4 PK, double *mom,
                                  double *mass) {
  forRows(st, k, [&](PetscInt nd, double w, const Vector<3> &) GIMP_LANES_LAMBDA {
    store3(mom + 3 * nd, load3(mom + 3 * nd) + splat(w) * PK);
    if (mass) mass[3 * nd] += w * mp;
  });
}

/// particleFromGrid<3> of a particle that keeps rows.
GIMP_LANES_INLINE void fromGridRows(const Stencils<3> &st, PetscInt k, const double *vg,
                                    const double *ag, V4 &VP, V4 &AP) {
  VP = AP = splat(0.0);
  forRows(st, k, [&](PetscInt nd, double w, const Vector<3> &) GIMP_LANES_LAMBDA {
    VP = VP + splat(w) * load3(vg + 3 * nd);
    AP = AP + splat(w) * load3(ag + 3 * nd);
  });
}

/// particleToGridAffineB<3>, block branch: D_k from the three axes' 1D moments, C = B D^-1, and
/// node (i, j, q) gets m w_j w_q [w_i (v + C_y dy_j + C_z dz_q) + w_i dx_i C_x].
GIMP_LANES_INLINE void affineToGrid(const Block<3> &b, double mp, V4 V, const Tensor<3> &Bk,
                                    const double *xk, const double *xs, double *mom, double *mass) {
  double d[3][3], S[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  const PetscInt step[3] = {1, b.stride[0], b.stride[1]};
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < 3; ++i) {
      d[a][i] = xs[3 * (b.base + i * step[a]) + a] - xk[a];
      const double w = b.w[a][i];
      S[a][0] += w;
      S[a][1] += w * d[a][i];
      S[a][2] += w * d[a][i] * d[a][i];
    }
  const Tensor<3> Ck =
      product<3>(Bk, invertInertia(S[0][2] * S[1][0] * S[2][0], S[0][0] * S[1][2] * S[2][0],
                                   S[0][0] * S[1][0] * S[2][2], S[0][1] * S[1][1] * S[2][0],
                                   S[0][1] * S[1][0] * S[2][1], S[0][0] * S[1][1] * S[2][1]));
  const V4 Cx = column(Ck, 0), Cy = column(Ck, 1), Cz = column(Ck, 2);
  for (int q = 0; q < 3; ++q)
    for (int j = 0; j < 3; ++j) {
      const double mw = mp * b.w[1][j] * b.w[2][q];
      const V4 MW = splat(mw);
      const V4 R = MW * (V + Cy * splat(d[1][j]) + Cz * splat(d[2][q])), T = MW * Cx;
      const PetscInt row = b.base + j * b.stride[0] + q * b.stride[1];
      double *mr = mom + 3 * row;
      for (int i = 0; i < 3; ++i) {
        const double wx = b.w[0][i], wdx = wx * d[0][i];
        store3(mr + 3 * i, load3(mr + 3 * i) + (splat(wx) * R + splat(wdx) * T));
        if (mass) mass[3 * (row + i)] += wx * mw;
      }
    }
}

/// particleFromGridAffine<3>, block branch: v_p and the columns of B_p (row sums along x, then
/// the (y, z) factors).
GIMP_LANES_INLINE void affineFromGrid(const Block<3> &b, const double *vg, const double *xk,
                                      const double *xs, V4 &VP, V4 *Bc) {
  double dx[3];
  for (int i = 0; i < 3; ++i)
    dx[i] = xs[3 * (b.base + i)] - xk[0];
  VP = Bc[0] = Bc[1] = Bc[2] = splat(0.0);
  for (int q = 0; q < 3; ++q) {
    const double dz = xs[3 * (b.base + q * b.stride[1]) + 2] - xk[2];
    for (int j = 0; j < 3; ++j) {
      const PetscInt r = 3 * (b.base + j * b.stride[0] + q * b.stride[1]);
      const double dy = xs[r + 1] - xk[1], wyz = b.w[1][j] * b.w[2][q];
      V4 T = splat(0.0), U = splat(0.0);
      for (int i = 0; i < 3; ++i) {
        const V4 WV = splat(b.w[0][i]) * load3(vg + r + 3 * i);
        T = T + WV;
        U = U + WV * splat(dx[i]);
      }
      const V4 W = splat(wyz);
      VP = VP + W * T;
      Bc[0] = Bc[0] + W * U;
      Bc[1] = Bc[1] + splat(wyz * dy) * T;
      Bc[2] = Bc[2] + splat(wyz * dz) * T;
    }
  }
}

/// APIC G2P of every particle, with the re-projection into mom when it is not null.
GIMP_LANES_INLINE void affineG2P(const Stencils<3> &st, PetscInt n, const double *vg,
                                 const double *xc, const double *xs, double dt, const double *m,
                                 double *v, double *B, double *x, double *mom) {
  for (PetscInt k = 0; k < n; ++k) {
    const double *xk = xc + 3 * k;
    V4 VP, Bc[3];
    Tensor<3> Bk;
    if (st.isBlock(k)) {
      const Block<3> b = st.block(k);
      affineFromGrid(b, vg, xk, xs, VP, Bc);
      setColumns(Bc, Bk);
      if (mom) affineToGrid(b, m[k], VP, Bk, xk, xs, mom, nullptr);
    } else {
      affineFromGridRows(st, k, vg, xk, xs, VP, Bc);
      setColumns(Bc, Bk);
      if (mom) affineToGridRows(st, k, m[k], VP, Bk, xk, xs, mom, nullptr);
    }
    tensorAt<3>(B, k) = Bk;
    store3(v + 3 * k, VP);
    if (x) store3(x + 3 * k, load3(x + 3 * k) + splat(dt) * VP);
  }
}

/// particleToGrid<3> through Stencils::forEach's walk of a block: m_p v_p w into mom, m_p w into
/// mass.
GIMP_LANES_INLINE void toGrid(const Block<3> &b, double mp, V4 PK, double *mom, double *mass) {
  int nn[3];
  reached(b, nn);
  for (int q = 0; q < nn[2]; ++q)
    for (int j = 0; j < nn[1]; ++j) {
      const double wyz = b.w[1][j] * b.w[2][q];
      const PetscInt row = b.base + j * b.stride[0] + q * b.stride[1];
      for (int i = 0; i < nn[0]; ++i) {
        const double w = b.w[0][i] * wyz;
        double *mr = mom + 3 * (row + i);
        store3(mr, load3(mr) + splat(w) * PK);
        if (mass) mass[3 * (row + i)] += w * mp;
      }
    }
}

/// particleFromGrid<3> through the same walk: the grid velocity and acceleration at the particle.
GIMP_LANES_INLINE void fromGrid(const Block<3> &b, const double *vg, const double *ag, V4 &VP,
                                V4 &AP) {
  int nn[3];
  reached(b, nn);
  VP = AP = splat(0.0);
  for (int q = 0; q < nn[2]; ++q)
    for (int j = 0; j < nn[1]; ++j) {
      const double wyz = b.w[1][j] * b.w[2][q];
      const PetscInt r = 3 * (b.base + j * b.stride[0] + q * b.stride[1]);
      for (int i = 0; i < nn[0]; ++i) {
        const V4 W = splat(b.w[0][i] * wyz);
        VP = VP + W * load3(vg + r + 3 * i);
        AP = AP + W * load3(ag + r + 3 * i);
      }
    }
}

/// FLIP/PIC G2P of every particle, with the re-projection into mom when it is not null.
GIMP_LANES_INLINE void flipG2P(const Stencils<3> &st, PetscInt n, const double *vg,
                               const double *ag, double dt, double flip, const double *m, double *v,
                               double *x, double *mom) {
  const V4 F = splat(flip), G = splat(1.0 - flip), DT = splat(dt);
  for (PetscInt k = 0; k < n; ++k) {
    const bool block = st.isBlock(k);
    V4 VP, AP;
    if (block)
      fromGrid(st.block(k), vg, ag, VP, AP);
    else
      fromGridRows(st, k, vg, ag, VP, AP);
    const V4 Vk = F * (load3(v + 3 * k) + DT * AP) + G * VP;
    store3(v + 3 * k, Vk);
    store3(x + 3 * k, load3(x + 3 * k) + DT * VP);
    if (!mom) continue;
    if (block)
      toGrid(st.block(k), m[k], splat(m[k]) * Vk, mom, nullptr);
    else
      toGridRows(st, k, m[k], splat(m[k]) * Vk, mom, nullptr);
  }
}

/// Entry e of the four row-major 3 x 3 tensors at a (36 doubles) in lanes: c[e] = (a[e], a[9 +
/// e], a[18 + e], a[27 + e]).
GIMP_LANES_INLINE void loadTensors4(const double *a, V4 *c) {
  for (int e = 0; e < 9; ++e)
    c[e] = _mm256_set_pd(a[27 + e], a[18 + e], a[9 + e], a[e]);
}
GIMP_LANES_INLINE void storeTensors4(double *a, const V4 *c) {
  alignas(32) double t[4];
  for (int e = 0; e < 9; ++e) {
    _mm256_store_pd(t, c[e]);
    for (int q = 0; q < 4; ++q)
      a[9 * q + e] = t[q];
  }
}
/// Component a of the four 3-vectors at p in lanes, and back.
GIMP_LANES_INLINE V4 loadComponent4(const double *p, int a) {
  return _mm256_set_pd(p[9 + a], p[6 + a], p[3 + a], p[a]);
}
GIMP_LANES_INLINE void storeComponent4(double *p, int a, V4 v) {
  alignas(32) double t[4];
  _mm256_store_pd(t, v);
  for (int q = 0; q < 4; ++q)
    p[3 * q + a] = t[q];
}

/// interpolateAt<3>: sum_i S_ip f_i at particle k (through Stencils::forEach's walk).
GIMP_LANES_INLINE V4 interpolate(const Stencils<3> &st, PetscInt k, const double *fg) {
  V4 FP = splat(0.0);
  if (!st.isBlock(k)) {
    forRows(st, k, [&](PetscInt nd, double w, const Vector<3> &) GIMP_LANES_LAMBDA {
      FP = FP + splat(w) * load3(fg + 3 * nd);
    });
    return FP;
  }
  const Block<3> b = st.block(k);
  int nn[3];
  reached(b, nn);
  for (int q = 0; q < nn[2]; ++q)
    for (int j = 0; j < nn[1]; ++j) {
      const double wyz = b.w[1][j] * b.w[2][q];
      const PetscInt r = 3 * (b.base + j * b.stride[0] + q * b.stride[1]);
      for (int i = 0; i < nn[0]; ++i)
        FP = FP + splat(b.w[0][i] * wyz) * load3(fg + r + 3 * i);
    }
  return FP;
}

} // namespace

GIMP_LANES void particlesToGridAffineB(const Stencils<3> &st, PetscInt n, const double *m,
                                       const double *v, const double *B, const double *xc,
                                       const double *xs, double *mom, double *mass) {
  for (PetscInt k = 0; k < n; ++k) {
    if (st.isBlock(k))
      affineToGrid(st.block(k), m[k], load3(v + 3 * k), tensorAt<3>(B, k), xc + 3 * k, xs, mom,
                   mass);
    else
      affineToGridRows(st, k, m[k], load3(v + 3 * k), tensorAt<3>(B, k), xc + 3 * k, xs, mom, mass);
  }
}

GIMP_LANES void gridToParticlesAffineProjected(const Stencils<3> &st, PetscInt n, const double *vg,
                                               const double *xc, const double *xs, double dt,
                                               const double *m, double *v, double *B, double *x,
                                               double *mom) {
  affineG2P(st, n, vg, xc, xs, dt, m, v, B, x, mom);
}

GIMP_LANES void gridToParticlesAffine(const Stencils<3> &st, PetscInt n, const double *vg,
                                      const double *xc, const double *xs, double dt, double *v,
                                      double *B, double *x) {
  affineG2P(st, n, vg, xc, xs, dt, nullptr, v, B, x, nullptr);
}

GIMP_LANES void particlesToGrid(const Stencils<3> &st, PetscInt n, const double *m, const double *v,
                                double *mom, double *mass) {
  for (PetscInt k = 0; k < n; ++k) {
    if (st.isBlock(k))
      toGrid(st.block(k), m[k], splat(m[k]) * load3(v + 3 * k), mom, mass);
    else
      toGridRows(st, k, m[k], splat(m[k]) * load3(v + 3 * k), mom, mass);
  }
}

GIMP_LANES void gridToParticles(const Stencils<3> &st, PetscInt n, const double *vg,
                                const double *ag, double dt, double flip, double *v, double *x) {
  flipG2P(st, n, vg, ag, dt, flip, nullptr, v, x, nullptr);
}

GIMP_LANES void gridToParticlesProjected(const Stencils<3> &st, PetscInt n, const double *vg,
                                         const double *ag, double dt, double flip, const double *m,
                                         double *v, double *x, double *mom) {
  flipG2P(st, n, vg, ag, dt, flip, m, v, x, mom);
}

GIMP_LANES void gridToParticlesAffineRated(const Stencils<3> &st, PetscInt n, const double *vg,
                                           const double *wg, const double *xs, double dt,
                                           const double *m, double *v, double *B, double *x,
                                           double *mom) {
  for (PetscInt k = 0; k < n; ++k) {
    const double *xk = x + 3 * k; // (the particle's place before it moves)
    V4 VP, Bc[3];
    Tensor<3> Bk;
    const bool block = st.isBlock(k);
    if (block)
      affineFromGrid(st.block(k), vg, xk, xs, VP, Bc);
    else
      affineFromGridRows(st, k, vg, xk, xs, VP, Bc);
    setColumns(Bc, Bk);
    const V4 WP = wg == vg ? VP : interpolate(st, k, wg);
    if (mom && block) affineToGrid(st.block(k), m[k], VP, Bk, xk, xs, mom, nullptr);
    if (mom && !block) affineToGridRows(st, k, m[k], VP, Bk, xk, xs, mom, nullptr);
    tensorAt<3>(B, k) = Bk;
    store3(v + 3 * k, VP);
    store3(x + 3 * k, load3(x + 3 * k) + splat(dt) * WP);
  }
}

GIMP_LANES void gridToParticlesRated(const Stencils<3> &st, PetscInt n, const double *ug,
                                     const double *wg, double dt, double flip, const double *m,
                                     double *v, double *x, double *mom) {
  const V4 F = splat(flip), DT = splat(dt);
  for (PetscInt k = 0; k < n; ++k) {
    const bool block = st.isBlock(k);
    V4 UP, WP;
    if (block)
      fromGrid(st.block(k), ug, wg, UP, WP);
    else
      fromGridRows(st, k, ug, wg, UP, WP);
    const V4 Vk = F * load3(v + 3 * k) + UP;
    store3(v + 3 * k, Vk);
    store3(x + 3 * k, load3(x + 3 * k) + DT * WP);
    if (!mom) continue;
    if (block)
      toGrid(st.block(k), m[k], splat(m[k]) * Vk, mom, nullptr);
    else
      toGridRows(st, k, m[k], splat(m[k]) * Vk, mom, nullptr);
  }
}

GIMP_LANES void internalForce(const Stencils<3> &st, PetscInt n, const double *V,
                              const double *stress, double *f) {
  for (PetscInt k = 0; k < n; ++k) {
    const Tensor<3> A = -V[k] * tensorAt<3>(stress, k);
    const V4 Ax = column(A, 0), Ay = column(A, 1), Az = column(A, 2), Z = splat(0.0);
    if (!st.isBlock(k)) { // transfer::internalForce<3> of a particle that keeps rows
      forRows(st, k, [&](PetscInt nd, double, const Vector<3> &gr) GIMP_LANES_LAMBDA {
        const V4 fc = Z + Ax * splat(gr[0]) + Ay * splat(gr[1]) + Az * splat(gr[2]);
        store3(f + 3 * nd, load3(f + 3 * nd) + fc);
      });
      continue;
    }
    const Block<3> b = st.block(k);
    int nn[3];
    reached(b, nn);
    for (int q = 0; q < nn[2]; ++q)
      for (int j = 0; j < nn[1]; ++j) {
        const double wyz = b.w[1][j] * b.w[2][q], gy = b.g[1][j] * b.w[2][q],
                     gz = b.w[1][j] * b.g[2][q];
        double *fr = f + 3 * (b.base + j * b.stride[0] + q * b.stride[1]);
        for (int i = 0; i < nn[0]; ++i) {
          const V4 fc = Z + Ax * splat(b.g[0][i] * wyz) + Ay * splat(b.w[0][i] * gy) +
                        Az * splat(b.w[0][i] * gz);
          store3(fr + 3 * i, load3(fr + 3 * i) + fc);
        }
      }
  }
}

GIMP_LANES void velocityGradients(const Stencils<3> &st, PetscInt k0, PetscInt k1, const double *vg,
                                  double *L) {
  for (PetscInt k = k0; k < k1; ++k) {
    auto Lk = tensorAt<3>(L, k - k0);
    if (!st.isBlock(k)) { // velocityGradientAt<3> of a particle that keeps rows
      V4 Lc[3] = {splat(0.0), splat(0.0), splat(0.0)};
      forRows(st, k, [&](PetscInt nd, double, const Vector<3> &gr) GIMP_LANES_LAMBDA {
        const V4 vn = load3(vg + 3 * nd);
        for (int a = 0; a < 3; ++a)
          Lc[a] = Lc[a] + vn * splat(gr[a]);
      });
      setColumns(Lc, Lk);
      continue;
    }
    // velocityGradientAt<3>, block branch: rows along x (sum_i g_i v and sum_i w_i v), then the
    // (y, z) factors; the columns of L in lanes.
    const Block<3> b = st.block(k);
    V4 Lc[3] = {splat(0.0), splat(0.0), splat(0.0)};
    for (int q = 0; q < 3; ++q)
      for (int j = 0; j < 3; ++j) {
        const double *r = vg + 3 * (b.base + j * b.stride[0] + q * b.stride[1]);
        V4 PG = splat(0.0), QW = splat(0.0);
        for (int i = 0; i < 3; ++i) {
          const V4 vn = load3(r + 3 * i);
          PG = PG + splat(b.g[0][i]) * vn;
          QW = QW + splat(b.w[0][i]) * vn;
        }
        const double wyz = b.w[1][j] * b.w[2][q], gy = b.g[1][j] * b.w[2][q],
                     gz = b.w[1][j] * b.g[2][q];
        Lc[0] = Lc[0] + splat(wyz) * PG;
        Lc[1] = Lc[1] + splat(gy) * QW;
        Lc[2] = Lc[2] + splat(gz) * QW;
      }
    setColumns(Lc, Lk);
  }
}

GIMP_LANES void updateDeformation(const Scene<3> &sc, ParticleView<3> &p, const double *L,
                                  double dt, PetscInt k0, PetscInt k1) {
  const bool stretch = sc.tracking == Tracking::Stretch;
  const bool lanes = stretch || sc.tracking == Tracking::None;
  const V4 DT = splat(dt), HALF = splat(0.5), TWO = splat(2.0);
  PetscInt k = k0;
  while (lanes && k + 4 <= k1) {
    const Material &mat = sc.materialOf(p.id[k]);
    if (mat.model != MaterialModel::Linear || &sc.materialOf(p.id[k + 1]) != &mat ||
        &sc.materialOf(p.id[k + 2]) != &mat || &sc.materialOf(p.id[k + 3]) != &mat) {
      physics::updateDeformation<3>(sc, p, L + 9 * (k - k0), dt, k, k + 1);
      ++k;
      continue;
    }
    V4 Lk[9], F[9], Fn[9], S[9];
    loadTensors4(L + 9 * (k - k0), Lk);
    loadTensors4(p.F + 9 * k, F);
    // physics::updateDeformation<3>: F += dt product<3>(L, F), entry (i, j) summed over m in order
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        Fn[3 * i + j] = F[3 * i + j] + DT * (Lk[3 * i] * F[j] + Lk[3 * i + 1] * F[3 + j] +
                                             Lk[3 * i + 2] * F[6 + j]);
    storeTensors4(p.F + 9 * k, Fn);
    // determinant<3>, expanded along the first row
    const V4 det = Fn[0] * (Fn[4] * Fn[8] - Fn[5] * Fn[7]) -
                   Fn[1] * (Fn[3] * Fn[8] - Fn[5] * Fn[6]) +
                   Fn[2] * (Fn[3] * Fn[7] - Fn[4] * Fn[6]);
    _mm256_storeu_pd(p.V + k, det * _mm256_loadu_pd(p.V0 + k));
    // material::jaumannUpdate (3D): the spin a, b, c and the six new entries in closed form
    loadTensors4(p.s + 9 * k, S);
    const V4 a = HALF * (Lk[1] - Lk[3]), b = HALF * (Lk[2] - Lk[6]), c = HALF * (Lk[5] - Lk[7]);
    const V4 s00 = S[0], s11 = S[4], s22 = S[8], s01 = S[1], s02 = S[2], s12 = S[5];
    const V4 lt = splat(mat.lambda) * (Lk[0] + Lk[4] + Lk[8]), mu2 = splat(2.0 * mat.mu),
             mu = splat(mat.mu);
    const V4 n00 = lt + mu2 * Lk[0] + TWO * (a * s01 + b * s02);
    const V4 n11 = lt + mu2 * Lk[4] + TWO * (c * s12 - a * s01);
    const V4 n22 = lt + mu2 * Lk[8] - TWO * (b * s02 + c * s12);
    const V4 n01 = mu * (Lk[1] + Lk[3]) + a * (s11 - s00) + b * s12 + c * s02;
    const V4 n02 = mu * (Lk[2] + Lk[6]) + b * (s22 - s00) + a * s12 - c * s01;
    const V4 n12 = mu * (Lk[5] + Lk[7]) + c * (s22 - s11) - a * s02 - b * s01;
    S[0] = s00 + DT * n00;
    S[4] = s11 + DT * n11;
    S[8] = s22 + DT * n22;
    S[1] = S[3] = s01 + DT * n01;
    S[2] = S[6] = s02 + DT * n02;
    S[5] = S[7] = s12 + DT * n12;
    storeTensors4(p.s + 9 * k, S);
    if (stretch) // tracking::updateDomain: l_a = |F e_a| l0_a (Eigen's norm: x0^2 + (x1^2 + x2^2))
      for (int ax = 0; ax < 3; ++ax) {
        const V4 x0 = Fn[ax], x1 = Fn[3 + ax], x2 = Fn[6 + ax];
        storeComponent4(p.l + 3 * k, ax,
                        _mm256_sqrt_pd(x0 * x0 + (x1 * x1 + x2 * x2)) *
                            loadComponent4(p.l0 + 3 * k, ax));
      }
    k += 4;
  }
  if (k < k1) physics::updateDeformation<3>(sc, p, L + 9 * (k - k0), dt, k, k1);
}

#else // no lanes here: never called (laneLoops::available() is false)

void particlesToGridAffineB(const Stencils<3> &, PetscInt, const double *, const double *,
                            const double *, const double *, const double *, double *, double *) {}
void gridToParticlesAffineProjected(const Stencils<3> &, PetscInt, const double *, const double *,
                                    const double *, double, const double *, double *, double *,
                                    double *, double *) {}
void gridToParticlesAffine(const Stencils<3> &, PetscInt, const double *, const double *,
                           const double *, double, double *, double *, double *) {}
void particlesToGrid(const Stencils<3> &, PetscInt, const double *, const double *, double *,
                     double *) {}
void gridToParticles(const Stencils<3> &, PetscInt, const double *, const double *, double, double,
                     double *, double *) {}
void gridToParticlesProjected(const Stencils<3> &, PetscInt, const double *, const double *, double,
                              double, const double *, double *, double *, double *) {}
void gridToParticlesAffineRated(const Stencils<3> &, PetscInt, const double *, const double *,
                                const double *, double, const double *, double *, double *,
                                double *, double *) {}
void gridToParticlesRated(const Stencils<3> &, PetscInt, const double *, const double *, double,
                          double, const double *, double *, double *, double *) {}
void internalForce(const Stencils<3> &, PetscInt, const double *, const double *, double *) {}
void velocityGradients(const Stencils<3> &, PetscInt, PetscInt, const double *, double *) {}
void updateDeformation(const Scene<3> &, ParticleView<3> &, const double *, double, PetscInt,
                       PetscInt) {}

#endif

} // namespace gimp::transfer::laneLoops3
