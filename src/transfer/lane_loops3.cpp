// 3D block particles with their three components in lanes (AVX2): see transfer/lane_loops3.hpp.
// Every lane expression below is the scalar one of the kernel named next to it, in the same order,
// contracted into fused multiply-adds where the compiler finds them (this file is built with
// contraction for AVX2 with FMA), so the results are the scalar ones to round-off. Lane 3 of every
// vector is zero and never stored.
//
// This file: the transfers (APIC and FLIP P2G and G2P, with and without the re-projection, and
// the rate classes' G2P); the internal force, the velocity gradient and the stress update are in
// lane_loops3_stress.cpp, the pieces both share in lane_runs3.hpp.
#include "gimp/transfer/lane_loops3.hpp"

#include "gimp/transfer/affine.hpp"
#include "gimp/transfer/transfer.hpp"

#include "lane_runs3.hpp"

namespace gimp::transfer::laneLoops {

#if GIMP_HAVE_LANES

namespace {

/// f(row's first slot, the row's node bits along x, d[i] = x_i - x_p along x, dy, dz, w_j w_q,
/// the row's x factors) for every row of level-block particle k: the walk of the tensor-product
/// kernels below (the nodes' offsets from the particle along each axis read once per block and
/// row, as a block's).
template <class F>
GIMP_LANES_INLINE void forLevelBlockRows(const Stencils<3> &st, PetscInt k, const double *xk,
                                         const double *xs, F &&f) {
  Stencils<3>::LevelRow r;
  const LevelBlock<3> *block = nullptr;
  double d[4] = {0.0, 0.0, 0.0, 0.0};
  for (auto rows = st.levelRows(k); rows.next(r);) {
    if (r.block != block) { // (a block's offsets along x, once)
      block = r.block;
      for (int i = 0; i < 4; ++i)
        d[i] = i < block->n[0] ? xs[3 * (block->base + i)] - xk[0] : 0.0;
    }
    f(r.slot, r.nodes, d, xs[3 * r.slot + 1] - xk[1], xs[3 * r.slot + 2] - xk[2], r.wyz, r.w0);
  }
}

/// affineToGridRows of a level-block particle, by rows as a block's (affineToGrid): D_p from each
/// row's moments along x (sum_i w_i, w_i d_i, w_i d_i^2 over its nodes), then each row's
/// R = m w_j w_q (v + C_y dy + C_z dz) and T = m w_j w_q C_x, node i getting w_i R + w_i d_i T.
GIMP_LANES_INLINE void affineToGridLevels(const Stencils<3> &st, PetscInt k, double mp, V4 V,
                                          const Tensor<3> &Bk, const double *xk, const double *xs,
                                          double *mom, double *mass) {
  double xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;
  forLevelBlockRows(st, k, xk, xs,
                    [&](PetscInt, unsigned nodes, const double *d, double dy, double dz, double wyz,
                        const double *w) GIMP_LANES_LAMBDA {
                      double s0 = 0, s1 = 0, s2 = 0;
                      for (int i = 0; i < 4; ++i)
                        if ((nodes >> i) & 1u) {
                          s0 += w[i];
                          s1 += w[i] * d[i];
                          s2 += w[i] * d[i] * d[i];
                        }
                      xx += wyz * s2;
                      xy += wyz * s1 * dy;
                      xz += wyz * s1 * dz;
                      yy += wyz * s0 * dy * dy;
                      yz += wyz * s0 * dy * dz;
                      zz += wyz * s0 * dz * dz;
                    });
  const Tensor<3> Ck = product<3>(Bk, invertInertia(xx, yy, zz, xy, xz, yz));
  const V4 Cx = column(Ck, 0), Cy = column(Ck, 1), Cz = column(Ck, 2);
  forLevelBlockRows(st, k, xk, xs,
                    [&](PetscInt row, unsigned nodes, const double *d, double dy, double dz,
                        double wyz, const double *w) GIMP_LANES_LAMBDA {
                      const double mw = mp * wyz;
                      const V4 MW = splat(mw);
                      const V4 R = MW * (V + Cy * splat(dy) + Cz * splat(dz)), T = MW * Cx;
                      for (int i = 0; i < 4; ++i)
                        if ((nodes >> i) & 1u) {
                          double *p = mom + 3 * (row + i);
                          store3(p, load3(p) + splat(w[i]) * R + splat(w[i] * d[i]) * T);
                          if (mass) mass[3 * (row + i)] += w[i] * mw;
                        }
                    });
}

/// affineFromGridRows of a level-block particle, by rows (affineFromGrid): per row T = sum_i
/// w_i v_i and U = sum_i w_i d_i v_i, then v_p += w_j w_q T and B's columns w_j w_q (U, dy T,
/// dz T).
GIMP_LANES_INLINE void affineFromGridLevels(const Stencils<3> &st, PetscInt k, const double *vg,
                                            const double *xk, const double *xs, V4 &VP, V4 *Bc) {
  VP = Bc[0] = Bc[1] = Bc[2] = splat(0.0);
  forLevelBlockRows(st, k, xk, xs,
                    [&](PetscInt row, unsigned nodes, const double *d, double dy, double dz,
                        double wyz, const double *w) GIMP_LANES_LAMBDA {
                      V4 T = splat(0.0), U = splat(0.0);
                      for (int i = 0; i < 4; ++i)
                        if ((nodes >> i) & 1u) {
                          const V4 vn = load3(vg + 3 * (row + i));
                          T = T + splat(w[i]) * vn;
                          U = U + splat(w[i] * d[i]) * vn;
                        }
                      const V4 W = splat(wyz);
                      VP = VP + W * T;
                      Bc[0] = Bc[0] + W * U;
                      Bc[1] = Bc[1] + splat(wyz * dy) * T;
                      Bc[2] = Bc[2] + splat(wyz * dz) * T;
                    });
}

/// particleToGridAffineB<3> of a particle that keeps rows: D_p (inertiaAbout, its columns in
/// lanes), C = B D^-1, and each entry's S m (v + C (x_i - x_p)) (particleToGridAffine).
GIMP_LANES_INLINE void affineToGridRows(const Stencils<3> &st, PetscInt k, double mp, V4 V,
                                        const Tensor<3> &Bk, const double *xk, const double *xs,
                                        double *mom, double *mass) {
  if (st.isLevels(k)) return affineToGridLevels(st, k, mp, V, Bk, xk, xs, mom, mass);
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
  if (st.isLevels(k)) return affineFromGridLevels(st, k, vg, xk, xs, VP, Bc);
  VP = Bc[0] = Bc[1] = Bc[2] = splat(0.0);
  forRows(st, k, [&](PetscInt nd, double w, const Vector<3> &) GIMP_LANES_LAMBDA {
    const V4 WV = splat(w) * load3(vg + 3 * nd);
    VP = VP + WV;
    for (int a = 0; a < 3; ++a)
      Bc[a] = Bc[a] + WV * splat(xs[3 * nd + a] - xk[a]);
  });
}

/// particleToGrid<3> of particle k: m_p v_p S into mom, m_p S into mass (a block by rows along x,
/// each row's (y, z) factor applied once).
GIMP_LANES_INLINE void toGrid(const Stencils<3> &st, PetscInt k, double mp, V4 PK, double *mom,
                              double *mass) {
  if (!st.isBlock(k))
    return forRows(st, k, [&](PetscInt nd, double w, const Vector<3> &) GIMP_LANES_LAMBDA {
      store3(mom + 3 * nd, load3(mom + 3 * nd) + splat(w) * PK);
      if (mass) mass[3 * nd] += w * mp;
    });
  const Block<3> b = st.block(k);
  const RowFactors W = rowFactors(b.w[0]); // (a third node not reached has weight 0)
  const Spread P = spread(PK);
  forBlockRows(b, [&](PetscInt row, double wyz, int nx) GIMP_LANES_LAMBDA {
    addToRow(mom + 3 * row, W, wyz * P);
    if (mass) {
      const double mw = wyz * mp;
      for (int i = 0; i < nx; ++i)
        mass[3 * (row + i)] += b.w[0][i] * mw;
    }
  });
}

/// sum_i S_ip f_i and sum_i S_ip g_i at particle k (g null: the first only; a block by rows).
GIMP_LANES_INLINE void fromGrid(const Stencils<3> &st, PetscInt k, const double *fg,
                                const double *gg, V4 &FP, V4 &GP) {
  FP = GP = splat(0.0);
  if (!st.isBlock(k))
    return forRows(st, k, [&](PetscInt nd, double w, const Vector<3> &) GIMP_LANES_LAMBDA {
      FP = FP + splat(w) * load3(fg + 3 * nd);
      if (gg) GP = GP + splat(w) * load3(gg + 3 * nd);
    });
  const Block<3> b = st.block(k);
  forBlockRows(b, [&](PetscInt row, double wyz, int nx) GIMP_LANES_LAMBDA {
    V4 T = splat(0.0), U = splat(0.0);
    for (int i = 0; i < nx; ++i) {
      T = T + splat(b.w[0][i]) * load3(fg + 3 * (row + i));
      if (gg) U = U + splat(b.w[0][i]) * load3(gg + 3 * (row + i));
    }
    FP = FP + splat(wyz) * T;
    if (gg) GP = GP + splat(wyz) * U;
  });
}

/// interpolateAt<3>: sum_i S_ip f_i at particle k.
GIMP_LANES_INLINE V4 interpolate(const Stencils<3> &st, PetscInt k, const double *fg) {
  V4 FP, unused;
  fromGrid(st, k, fg, nullptr, FP, unused);
  return FP;
}

/// particleToGridAffineB<3>, block branch: D_k from the three axes' 1D moments, C = B D^-1, and
/// node (i, j, q) gets m w_j w_q [w_i (v + C_y dy_j + C_z dz_q) + w_i dx_i C_x], a row's three
/// nodes at once (RowFactors).
GIMP_LANES_INLINE void affineToGrid(const Block<3> &b, double mp, V4 V, const Tensor<3> &Bk,
                                    const double *xk, const double *xs, double *mom, double *mass) {
  double d[3][3];
  const Tensor<3> Ck = blockAffineVelocity(b, Bk, xk, xs, d);
  const V4 Cx = column(Ck, 0), Cy = column(Ck, 1), Cz = column(Ck, 2);
  const double wdx[3] = {b.w[0][0] * d[0][0], b.w[0][1] * d[0][1], b.w[0][2] * d[0][2]};
  const RowFactors W = rowFactors(b.w[0]), WD = rowFactors(wdx);
  for (int q = 0; q < 3; ++q)
    for (int j = 0; j < 3; ++j) {
      const double mw = mp * b.w[1][j] * b.w[2][q];
      const V4 MW = splat(mw);
      const V4 R = MW * (V + Cy * splat(d[1][j]) + Cz * splat(d[2][q])), T = MW * Cx;
      const PetscInt row = b.base + j * b.stride[0] + q * b.stride[1];
      addToRow(mom + 3 * row, W, spread(R), WD, spread(T));
      if (mass)
        for (int i = 0; i < 3; ++i)
          mass[3 * (row + i)] += b.w[0][i] * mw;
    }
}

/// particleFromGridAffine<3>, block branch: v_p and the columns of B_p (row sums along x, then
/// the (y, z) factors). With Mean, also WP = sum_i S_ip w_i of a second field wg from the same
/// walk: interpolate's sums in interpolate's order (the nodes a block does not reach have weight
/// zero and add exact zeros), so WP is bit for bit the separate interpolation.
template <bool Mean = false>
GIMP_LANES_INLINE void affineFromGrid(const Block<3> &b, const double *vg, const double *xk,
                                      const double *xs, V4 &VP, V4 *Bc, const double *wg = nullptr,
                                      V4 *WP = nullptr) {
  double wdx[3];
  for (int i = 0; i < 3; ++i)
    wdx[i] = b.w[0][i] * (xs[3 * (b.base + i)] - xk[0]);
  VP = Bc[0] = Bc[1] = Bc[2] = splat(0.0);
  if constexpr (Mean) *WP = splat(0.0);
  for (int q = 0; q < 3; ++q) {
    const double dz = xs[3 * (b.base + q * b.stride[1]) + 2] - xk[2];
    for (int j = 0; j < 3; ++j) {
      const PetscInt r = 3 * (b.base + j * b.stride[0] + q * b.stride[1]);
      const double dy = xs[r + 1] - xk[1], wyz = b.w[1][j] * b.w[2][q];
      V4 T = splat(0.0), U = splat(0.0), M = splat(0.0);
      for (int i = 0; i < 3; ++i) {
        const V4 vn = load3(vg + r + 3 * i);
        T = T + splat(b.w[0][i]) * vn;
        U = U + splat(wdx[i]) * vn;
        if constexpr (Mean) M = M + splat(b.w[0][i]) * load3(wg + r + 3 * i);
      }
      const V4 W = splat(wyz);
      VP = VP + W * T;
      Bc[0] = Bc[0] + W * U;
      Bc[1] = Bc[1] + splat(wyz * dy) * T;
      Bc[2] = Bc[2] + splat(wyz * dz) * T;
      if constexpr (Mean) *WP = *WP + W * M;
    }
  }
}

/// APIC G2P of every particle, with the re-projection into mom when it is not null.
GIMP_LANES_INLINE void affineG2P(const Stencils<3> &st, PetscInt n, const double *vg,
                                 const double *xc, const double *xs, double dt, const double *m,
                                 double *v, double *B, double *x, double *mom) {
  for (PetscInt k = 0; k < n; ++k) {
    prefetchRecord(st, k, n);
    if (k % 4 == 0)
      prefetch::fields(k, n, prefetch::Field<3>{xc}, prefetch::Field<9>{B}, prefetch::Field<3>{v});
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

/// FLIP/PIC G2P of every particle, with the re-projection into mom when it is not null: with Rated
/// false (gridToParticles<3>) v_p <- flip (v_p + dt S a) + (1 - flip) S v and x_p += dt S v (f0
/// = v, f1 = a); with Rated true (gridToParticlesRated<3>) v_p <- flip v_p + S u and x_p += dt S w
/// (f0 = u, f1 = w).
template <bool Rated>
GIMP_LANES_INLINE void flipG2P(const Stencils<3> &st, PetscInt n, const double *f0,
                               const double *f1, double dt, double flip, const double *m, double *v,
                               double *x, double *mom) {
  const V4 F = splat(flip), G = splat(1.0 - flip), DT = splat(dt);
  for (PetscInt k = 0; k < n; ++k) {
    prefetchRecord(st, k, n);
    V4 P0, P1;
    fromGrid(st, k, f0, f1, P0, P1);
    const V4 Vk = Rated ? F * load3(v + 3 * k) + P0 : F * (load3(v + 3 * k) + DT * P1) + G * P0;
    store3(v + 3 * k, Vk);
    store3(x + 3 * k, load3(x + 3 * k) + DT * (Rated ? P1 : P0));
    if (mom) toGrid(st, k, m[k], splat(m[k]) * Vk, mom, nullptr);
  }
}

} // namespace

GIMP_LANES void particlesToGridAffineB(const Stencils<3> &st, PetscInt n, const double *m,
                                       const double *v, const double *B, const double *xc,
                                       const double *xs, double *mom, double *mass) {
  for (PetscInt k = 0; k < n; ++k) {
    prefetchRecord(st, k, n);
    if (k % 4 == 0)
      prefetch::fields(k, n, prefetch::Field<3>{xc}, prefetch::Field<3>{v}, prefetch::Field<9>{B},
                       prefetch::Field<1>{m});
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
    prefetchRecord(st, k, n);
    toGrid(st, k, m[k], splat(m[k]) * load3(v + 3 * k), mom, mass);
  }
}

GIMP_LANES void gridToParticles(const Stencils<3> &st, PetscInt n, const double *vg,
                                const double *ag, double dt, double flip, double *v, double *x) {
  flipG2P<false>(st, n, vg, ag, dt, flip, nullptr, v, x, nullptr);
}

GIMP_LANES void gridToParticlesProjected(const Stencils<3> &st, PetscInt n, const double *vg,
                                         const double *ag, double dt, double flip, const double *m,
                                         double *v, double *x, double *mom) {
  flipG2P<false>(st, n, vg, ag, dt, flip, m, v, x, mom);
}

GIMP_LANES void gridToParticlesAffineRated(const Stencils<3> &st, PetscInt n, const double *vg,
                                           const double *wg, const double *xs, double dt,
                                           const double *m, double *v, double *B, double *x,
                                           double *mom) {
  for (PetscInt k = 0; k < n; ++k) {
    prefetchRecord(st, k, n);
    const double *xk = x + 3 * k; // (the particle's place before it moves)
    V4 VP, Bc[3];
    Tensor<3> Bk;
    const bool block = st.isBlock(k);
    V4 WP;
    if (block && wg != vg)
      affineFromGrid<true>(st.block(k), vg, xk, xs, VP, Bc, wg, &WP);
    else if (block)
      affineFromGrid(st.block(k), vg, xk, xs, VP, Bc);
    else
      affineFromGridRows(st, k, vg, xk, xs, VP, Bc);
    if (wg == vg)
      WP = VP;
    else if (!block)
      WP = interpolate(st, k, wg);
    setColumns(Bc, Bk);
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
  flipG2P<true>(st, n, ug, wg, dt, flip, m, v, x, mom);
}

#else // no lanes on this architecture (laneLoops::available() is false): the scalar loops

void particlesToGridAffineB(const Stencils<3> &st, PetscInt n, const double *m, const double *v,
                            const double *B, const double *xc, const double *xs, double *mom,
                            double *mass) {
  transfer::particlesToGridAffineB<3>(st, n, m, v, B, xc, xs, mom, mass);
}
void gridToParticlesAffineProjected(const Stencils<3> &st, PetscInt n, const double *vg,
                                    const double *xc, const double *xs, double dt, const double *m,
                                    double *v, double *B, double *x, double *mom) {
  transfer::gridToParticlesAffineProjected<3>(st, n, vg, xc, xs, dt, m, v, B, x, mom);
}
void gridToParticlesAffine(const Stencils<3> &st, PetscInt n, const double *vg, const double *xc,
                           const double *xs, double dt, double *v, double *B, double *x) {
  transfer::gridToParticlesAffine<3>(st, n, vg, xc, xs, dt, v, B, x);
}
void particlesToGrid(const Stencils<3> &st, PetscInt n, const double *m, const double *v,
                     double *mom, double *mass) {
  transfer::particlesToGrid<3>(st, n, m, v, mom, mass);
}
void gridToParticles(const Stencils<3> &st, PetscInt n, const double *vg, const double *ag,
                     double dt, double flip, double *v, double *x) {
  transfer::gridToParticles<3>(st, n, vg, ag, dt, flip, v, x);
}
void gridToParticlesProjected(const Stencils<3> &st, PetscInt n, const double *vg, const double *ag,
                              double dt, double flip, const double *m, double *v, double *x,
                              double *mom) {
  transfer::gridToParticlesProjected<3>(st, n, vg, ag, dt, flip, m, v, x, mom);
}
void gridToParticlesAffineRated(const Stencils<3> &st, PetscInt n, const double *vg,
                                const double *wg, const double *xs, double dt, const double *m,
                                double *v, double *B, double *x, double *mom) {
  transfer::gridToParticlesAffineRated<3>(st, n, vg, wg, xs, dt, m, v, B, x, mom);
}
void gridToParticlesRated(const Stencils<3> &st, PetscInt n, const double *ug, const double *wg,
                          double dt, double flip, const double *m, double *v, double *x,
                          double *mom) {
  transfer::gridToParticlesRated<3>(st, n, ug, wg, dt, flip, m, v, x, mom);
}

#endif

} // namespace gimp::transfer::laneLoops
