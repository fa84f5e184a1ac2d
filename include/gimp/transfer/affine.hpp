// Affine particle-in-cell transfers (APIC, Jiang et al. 2015) and the projections of XPIC(m)
// (Hammerquist & Nairn 2017) as free kernels over explicit arrays, for any dimension D.
//
// Nodal arrays are window arrays (D values per slot) as in transfer.hpp; xs holds the D
// coordinates of every slot (a crack's second slot has its node's coordinates), xc the weight
// centres of the particles (the centres the stencils were built at). Every moment is taken with
// the step's own stencil weights S_ip, so the inertia D_p below is exact for GIMP weights on any
// level, at transition nodes and at cracked slots alike.
#pragma once

#include "gimp/grid/stencils.hpp"
#include "gimp/transfer/block_kernels.hpp"
#include "gimp/transfer/transfer.hpp"

#include <Eigen/LU>

#include <cmath>

namespace gimp::transfer {

/// x_p = sum_i S_ip x_i for every particle: the point its weights are centred at (into xc).
/// Moments about any other point y see an affine field v = a + G x as
/// B = v(x_p) (x_p - y)^T + G D: a gradient made of the velocity itself.
template <int D>
void weightCentroids(const Stencils<D> &st, PetscInt n, const double *xs, double *xc) {
  for (PetscInt k = 0; k < n; ++k) {
    double c[D] = {};
    st.forEach(k, [&](PetscInt nd, double w, const Vector<D> &) {
      for (int a = 0; a < D; ++a)
        c[a] += w * xs[D * nd + a];
    });
    for (int a = 0; a < D; ++a)
      xc[D * k + a] = c[a];
  }
}

/// D_p = sum_i S_ip (x_i - x_p)(x_i - x_p)^T of particle k, with x_p = xk (D values).
template <int D>
Tensor<D> inertiaAbout(const Stencils<D> &st, PetscInt k, const double *xk, const double *xs) {
  Tensor<D> Dp = Tensor<D>::Zero();
  st.forEach(k, [&](PetscInt nd, double w, const Vector<D> &) {
    double dx[D];
    for (int a = 0; a < D; ++a)
      dx[a] = xs[D * nd + a] - xk[a];
    for (int a = 0; a < D; ++a)
      for (int b = 0; b < D; ++b)
        Dp(a, b) += w * dx[a] * dx[b];
  });
  return Dp;
}

/// D_p of particle k about its centre in xc (D values per particle).
template <int D>
Tensor<D> inertia(const Stencils<D> &st, PetscInt k, const double *xc, const double *xs) {
  return inertiaAbout<D>(st, k, xc + D * k, xs);
}

/// The inverse of a symmetric 3 x 3 inertia (xx, yy, zz, xy, xz, yz) by its adjugate, or 0 where
/// it is singular (the rule of inverseInertiaAbout).
inline Tensor<3> invertInertia(double xx, double yy, double zz, double xy, double xz, double yz) {
  const double a00 = yy * zz - yz * yz, a01 = xz * yz - xy * zz, a02 = xy * yz - xz * yy;
  const double det = xx * a00 + xy * a01 + xz * a02;
  const double third = (xx + yy + zz) / 3.0;
  if (!(det > 1e-12 * third * third * third)) return Tensor<3>::Zero();
  const double id = 1.0 / det;
  const double a11 = xx * zz - xz * xz, a12 = xy * xz - xx * yz, a22 = xx * yy - xy * xy;
  Tensor<3> r;
  r << a00 * id, a01 * id, a02 * id, a01 * id, a11 * id, a12 * id, a02 * id, a12 * id, a22 * id;
  return r;
}

/// D_p^-1 of a particle's inertia D_p. Where D_p is singular (its determinant below 1e-12 of
/// (trace / D)^D: a particle whose weights all sit on one line of nodes) the inverse is taken as
/// 0, so C_p = 0 and the particle transfers as in PIC.
template <int D> Tensor<D> inverseOfInertia(const Tensor<D> &Dp) {
  // Closed forms: no pow, no general inverse in the per-particle loop (D_p is symmetric: its
  // (a, b) and (b, a) sums are the same products in the same order).
  if constexpr (D == 2)
    return invertInertia(Dp(0, 0), Dp(0, 1), Dp(1, 0), Dp(1, 1));
  else
    return invertInertia(Dp(0, 0), Dp(1, 1), Dp(2, 2), Dp(0, 1), Dp(0, 2), Dp(1, 2));
}

/// D_p^-1 of particle k about xk (inverseOfInertia's rule).
template <int D>
Tensor<D> inverseInertiaAbout(const Stencils<D> &st, PetscInt k, const double *xk,
                              const double *xs) {
  return inverseOfInertia<D>(inertiaAbout<D>(st, k, xk, xs));
}

/// D_p^-1 of particle k about its centre in xc.
template <int D>
Tensor<D> inverseInertia(const Stencils<D> &st, PetscInt k, const double *xc, const double *xs) {
  return inverseInertiaAbout<D>(st, k, xc + D * k, xs);
}

/// C = B D^-1 of a 3D block particle at xk, and the offsets d[a][i] = x_i - x_p of its nodes along
/// each axis. A block's nodes are regular, whose weights sum to 1 and reproduce linear functions
/// along each axis (sum_i w_i = 1, sum_i w_i d_i = 0 to round-off), so D_p = diag(S2_x, S2_y,
/// S2_z) with S2_a = sum_i w_i d_i^2 along axis a; where D_p is singular as invertInertia decides
/// (det below 1e-12 (tr / 3)^3), C = 0.
GIMP_ALWAYS_INLINE Tensor<3> blockAffineVelocity(const Block<3> &b, const Tensor<3> &Bk,
                                                 const double *xk, const double *xs,
                                                 double (&d)[3][3]) {
  double S2[3] = {0, 0, 0};
  const PetscInt step[3] = {1, b.stride[0], b.stride[1]};
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < 3; ++i) {
      d[a][i] = xs[3 * (b.base + i * step[a]) + a] - xk[a];
      S2[a] += b.w[a][i] * d[a][i] * d[a][i];
    }
  const double third = (S2[0] + S2[1] + S2[2]) / 3.0;
  if (!(S2[0] * S2[1] * S2[2] > 1e-12 * third * third * third)) return Tensor<3>::Zero();
  const double i0 = 1.0 / S2[0], i1 = 1.0 / S2[1], i2 = 1.0 / S2[2];
  Tensor<3> C;
  for (int r = 0; r < 3; ++r) {
    C(r, 0) = Bk(r, 0) * i0;
    C(r, 1) = Bk(r, 1) * i1;
    C(r, 2) = Bk(r, 2) * i2;
  }
  return C;
}

/// C_p = B_p D_p^-1 for every particle (row-major D x D into C).
template <int D>
void affineVelocity(const Stencils<D> &st, PetscInt n, const double *xc, const double *xs,
                    const double *B, double *C) {
  for (PetscInt k = 0; k < n; ++k)
    tensorAt<D>(C, k) = product<D>(tensorAt<D>(B, k), inverseInertia<D>(st, k, xc, xs));
}

/// APIC P2G of particle k with affine velocity C: nodal momentum S_ip m_p (v_p + C (x_i - x_p))
/// into mom and, when mass is not null, S_ip m_p into component 0 of mass.
template <int D, class Ct>
GIMP_ALWAYS_INLINE void particleToGridAffine(const Stencils<D> &st, PetscInt k, double mp,
                                             const double *vk, const Ct &Ck, const double *xk,
                                             const double *xs, double *mom, double *mass) {
  st.forEach(k, [&](PetscInt nd, double w, const Vector<D> &) {
    double dx[D];
    for (int a = 0; a < D; ++a)
      dx[a] = xs[D * nd + a] - xk[a];
    for (int c = 0; c < D; ++c) {
      double vc = vk[c];
      for (int a = 0; a < D; ++a)
        vc += Ck(c, a) * dx[a];
      mom[D * nd + c] += w * mp * vc;
    }
    if (mass) mass[D * nd] += w * mp;
  });
}

/// APIC P2G: nodal momentum sum_p S_ip m_p (v_p + C_p (x_i - x_p)) into mom and, when mass is
/// not null, nodal mass sum_p S_ip m_p into component 0 of mass (both accumulated).
template <int D>
void particlesToGridAffine(const Stencils<D> &st, PetscInt n, const double *m, const double *v,
                           const double *C, const double *xc, const double *xs, double *mom,
                           double *mass) {
  for (PetscInt k = 0; k < n; ++k)
    particleToGridAffine<D>(st, k, m[k], v + D * k, tensorAt<D>(C, k), xc + D * k, xs, mom, mass);
}

/// APIC P2G of particle k with C = B_k D_k^-1 formed from its stencil (for a block, D_k from the
/// 1D moments of each axis and the momentum of node (i, j) as m w_j [w_i (v + C e_y dy_j) +
/// w_i dx_i C e_x]).
template <int D>
GIMP_ALWAYS_INLINE void particleToGridAffineB(const Stencils<D> &st, PetscInt k, double mp,
                                              const double *vk, const Tensor<D> &Bk,
                                              const double *xk, const double *xs, double *mom,
                                              double *mass) {
  if constexpr (D == 2) {
    if (st.isBlock(k)) return blocks::affineToGrid(st.block(k), mp, vk, Bk, xk, xs, mom, mass);
    if (st.isBlock4(k)) return blocks::affineToGrid(st.block4(k), mp, vk, Bk, xk, xs, mom, mass);
  }
  if constexpr (D == 3)
    if (st.isBlock(k)) { // the same in 3D: D_k from the three axes' 1D moments, rows along x
      const Block<3> b = st.block(k);
      double d[3][3];
      const Tensor<3> Ck = blockAffineVelocity(b, Bk, xk, xs, d);
      for (int q = 0; q < 3; ++q)
        for (int j = 0; j < 3; ++j) {
          const double mw = mp * b.w[1][j] * b.w[2][q];
          double r[3], t[3];
          for (int c = 0; c < 3; ++c) {
            r[c] = mw * (vk[c] + Ck(c, 1) * d[1][j] + Ck(c, 2) * d[2][q]);
            t[c] = mw * Ck(c, 0);
          }
          const PetscInt row = b.base + j * b.stride[0] + q * b.stride[1];
          double *mr = mom + 3 * row;
          for (int i = 0; i < 3; ++i) {
            const double wx = b.w[0][i], wdx = wx * d[0][i];
            for (int c = 0; c < 3; ++c)
              mr[3 * i + c] += wx * r[c] + wdx * t[c];
            if (mass) mass[3 * (row + i)] += wx * mw;
          }
        }
      return;
    }
  const Tensor<D> Ck = product<D>(Bk, inverseInertiaAbout<D>(st, k, xk, xs));
  particleToGridAffine<D>(st, k, mp, vk, Ck, xk, xs, mom, mass);
}

/// The same for every particle, C_p = B_p D_p^-1 formed per particle from its stencil (no
/// per-particle arrays): the step's P2G.
template <int D>
void particlesToGridAffineB(const Stencils<D> &st, PetscInt n, const double *m, const double *v,
                            const double *B, const double *xc, const double *xs, double *mom,
                            double *mass) {
  for (PetscInt k = 0; k < n; ++k)
    particleToGridAffineB<D>(st, k, m[k], v + D * k, tensorAt<D>(B, k), xc + D * k, xs, mom, mass);
}

/// One entry (slot nd, weight w) of the APIC gather about xk: its S v into vp and S v (x_i -
/// x_p)^T into Bk; with Inertia also S (x_i - x_p)(x_i - x_p)^T into Dp (inertiaAbout's sum).
template <int D, bool Inertia>
GIMP_ALWAYS_INLINE void gatherAffineEntry(PetscInt nd, double w, const double *vg, const double *xk,
                                          const double *xs, double *vp, Tensor<D> &Bk,
                                          Tensor<D> *Dp) {
  double dx[D];
  for (int a = 0; a < D; ++a)
    dx[a] = xs[D * nd + a] - xk[a];
  for (int c = 0; c < D; ++c) {
    const double wv = w * vg[D * nd + c];
    vp[c] += wv;
    for (int a = 0; a < D; ++a)
      Bk(c, a) += wv * dx[a];
  }
  if constexpr (Inertia)
    for (int a = 0; a < D; ++a)
      for (int b = 0; b < D; ++b)
        (*Dp)(a, b) += w * dx[a] * dx[b];
}

/// APIC G2P of particle k: v_p = sum_i S_ip v_i into vp, B_p = sum_i S_ip v_i (x_i - x_p)^T into
/// Bk (x_p = xk, the stencil's centre).
template <int D>
GIMP_ALWAYS_INLINE void particleFromGridAffine(const Stencils<D> &st, PetscInt k, const double *vg,
                                               const double *xk, const double *xs, double *vp,
                                               Tensor<D> &Bk) {
  for (int c = 0; c < D; ++c)
    vp[c] = 0.0;
  Bk = Tensor<D>::Zero();
  if constexpr (D == 2) { // row sums along x, then along y; both components at once
    if (st.isBlock(k)) return blocks::affineFromGrid(st.block(k), vg, xk, xs, vp, Bk);
    if (st.isBlock4(k)) return blocks::affineFromGrid(st.block4(k), vg, xk, xs, vp, Bk);
  }
  if constexpr (D == 3)
    if (st.isBlock(k)) { // row sums along x, then the (y, z) factors
      const Block<3> b = st.block(k);
      double dx[3];
      for (int i = 0; i < 3; ++i)
        dx[i] = xs[3 * (b.base + i)] - xk[0];
      for (int q = 0; q < 3; ++q) {
        const double dz = xs[3 * (b.base + q * b.stride[1]) + 2] - xk[2];
        for (int j = 0; j < 3; ++j) {
          const PetscInt r = 3 * (b.base + j * b.stride[0] + q * b.stride[1]);
          const double dy = xs[r + 1] - xk[1], wyz = b.w[1][j] * b.w[2][q];
          double t[3] = {0, 0, 0}, u[3] = {0, 0, 0};
          for (int i = 0; i < 3; ++i)
            for (int c = 0; c < 3; ++c) {
              const double wv = b.w[0][i] * vg[r + 3 * i + c];
              t[c] += wv;
              u[c] += wv * dx[i];
            }
          for (int c = 0; c < 3; ++c) {
            vp[c] += wyz * t[c];
            Bk(c, 0) += wyz * u[c];
            Bk(c, 1) += wyz * dy * t[c];
            Bk(c, 2) += wyz * dz * t[c];
          }
        }
      }
      return;
    }
  st.forEach(k, [&](PetscInt nd, double w, const Vector<D> &) {
    gatherAffineEntry<D, false>(nd, w, vg, xk, xs, vp, Bk, nullptr);
  });
}

/// APIC G2P of particle k (particleFromGridAffine) and the re-projection of its new v_p, B_p
/// into mom (particleToGridAffineB, no mass); a 2D block's offsets formed once for both, a row
/// particle's D_p (inertiaAbout's sums, in its order) in the gather's walk.
template <int D>
GIMP_ALWAYS_INLINE void particleFromAndToGridAffine(const Stencils<D> &st, PetscInt k, double mp,
                                                    const double *vg, const double *xk,
                                                    const double *xs, double *vp, Tensor<D> &Bk,
                                                    double *mom) {
  if constexpr (D == 2) {
    if (st.isBlock(k)) return blocks::affineFromAndToGrid(st.block(k), mp, vg, xk, xs, vp, Bk, mom);
    if (st.isBlock4(k))
      return blocks::affineFromAndToGrid(st.block4(k), mp, vg, xk, xs, vp, Bk, mom);
  }
  if (!st.isBlock(k) && !st.isLevels(k)) {
    for (int c = 0; c < D; ++c)
      vp[c] = 0.0;
    Bk = Tensor<D>::Zero();
    Tensor<D> Dp = Tensor<D>::Zero();
    const auto gather = [&](PetscInt nd, double w, const Vector<D> &) {
      gatherAffineEntry<D, true>(nd, w, vg, xk, xs, vp, Bk, &Dp);
    };
    st.forEachEntry(k, gather);
    const Tensor<D> Ck = product<D>(Bk, inverseOfInertia<D>(Dp));
    particleToGridAffine<D>(st, k, mp, vp, Ck, xk, xs, mom, nullptr);
    return;
  }
  particleFromGridAffine<D>(st, k, vg, xk, xs, vp, Bk);
  particleToGridAffineB<D>(st, k, mp, vp, Bk, xk, xs, mom, nullptr);
}

/// APIC G2P: v_p = sum_i S_ip v_i, B_p = sum_i S_ip v_i (x_i - x_p)^T, and the particle moves by
/// dt v_p. x may be the array xc points to: each particle reads its own centre before it moves;
/// with x null the particles stay (the caller moves them).
template <int D>
void gridToParticlesAffine(const Stencils<D> &st, PetscInt n, const double *vg, const double *xc,
                           const double *xs, double dt, double *v, double *B, double *x) {
  for (PetscInt k = 0; k < n; ++k) {
    double vp[D];
    Tensor<D> Bk;
    particleFromGridAffine<D>(st, k, vg, xc + D * k, xs, vp, Bk);
    tensorAt<D>(B, k) = Bk;
    for (int c = 0; c < D; ++c) {
      v[D * k + c] = vp[c];
      if (x) x[D * k + c] += dt * vp[c];
    }
  }
}

/// APIC G2P followed by the re-projection of the new affine momenta with the same stencils, in
/// one pass: gridToParticlesAffine, then particlesToGridAffineB of the new v_p and B_p into mom
/// (accumulated), the particles moving after their own re-projection (x may be xc).
template <int D>
void gridToParticlesAffineProjected(const Stencils<D> &st, PetscInt n, const double *vg,
                                    const double *xc, const double *xs, double dt, const double *m,
                                    double *v, double *B, double *x, double *mom) {
  for (PetscInt k = 0; k < n; ++k) {
    double vp[D];
    Tensor<D> Bk;
    particleFromAndToGridAffine<D>(st, k, m[k], vg, xc + D * k, xs, vp, Bk, mom);
    tensorAt<D>(B, k) = Bk;
    for (int c = 0; c < D; ++c) {
      v[D * k + c] = vp[c];
      x[D * k + c] += dt * vp[c];
    }
  }
}

/// The nodal field at each particle, out_p = sum_i S_ip f_i (D values per particle).
template <int D>
void interpolate(const Stencils<D> &st, PetscInt n, const double *fg, double *out) {
  for (PetscInt k = 0; k < n; ++k) {
    double fp[D] = {};
    st.forEach(k, [&](PetscInt nd, double w, const Vector<D> &) {
      for (int c = 0; c < D; ++c)
        fp[c] += w * fg[D * nd + c];
    });
    for (int c = 0; c < D; ++c)
      out[D * k + c] = fp[c];
  }
}

/// APIC G2P of one rate class of a multi-rate step: v_p = S v and B_p from the end velocity v,
/// the particle moving by dt S w with w the mean grid velocity over the class's step dt (w may
/// be v); with mom the new affine momenta are re-projected about the particle's place before it
/// moves.
template <int D>
void gridToParticlesAffineRated(const Stencils<D> &st, PetscInt n, const double *vg,
                                const double *wg, const double *xs, double dt, const double *m,
                                double *v, double *B, double *x, double *mom) {
  for (PetscInt k = 0; k < n; ++k) {
    double vp[D], wp[D];
    Tensor<D> Bk;
    particleFromGridAffine<D>(st, k, vg, x + D * k, xs, vp, Bk);
    if (wg == vg)
      for (int c = 0; c < D; ++c)
        wp[c] = vp[c];
    else
      interpolateAt<D>(st, k, wg, wp);
    if (mom) particleToGridAffineB<D>(st, k, m[k], vp, Bk, x + D * k, xs, mom, nullptr);
    tensorAt<D>(B, k) = Bk;
    for (int c = 0; c < D; ++c) {
      v[D * k + c] = vp[c];
      x[D * k + c] += dt * wp[c];
    }
  }
}

/// XPIC(m) G2P: v_p = sum_i S_ip (v*_i + dt a_i) with v* the filtered start velocity of the
/// step, and the particle moves by dt sum_i S_ip v_i (v the updated grid velocity).
template <int D>
void gridToParticlesFiltered(const Stencils<D> &st, PetscInt n, const double *vg, const double *ag,
                             const double *vstar, double dt, double *v, double *x) {
  for (PetscInt k = 0; k < n; ++k) {
    double vp[D] = {}, up[D] = {};
    st.forEach(k, [&](PetscInt nd, double w, const Vector<D> &) {
      for (int c = 0; c < D; ++c) {
        vp[c] += w * vg[D * nd + c];
        up[c] += w * (vstar[D * nd + c] + dt * ag[D * nd + c]);
      }
    });
    for (int c = 0; c < D; ++c) {
      v[D * k + c] = up[c];
      x[D * k + c] += dt * vp[c];
    }
  }
}

/// Total angular momentum (2D, about the origin) of APIC particles: sum_p m_p (x_p x v_p) plus
/// the affine field's spin m_p (B_yx - B_xy), which is sum_i S_ip m_p (x_i - x_p) x C_p (x_i -
/// x_p) with C_p = B_p D_p^-1.
inline double angularMomentum(PetscInt n, const double *m, const double *x, const double *v,
                              const double *B) {
  double L = 0;
  for (PetscInt k = 0; k < n; ++k)
    L += m[k] * (x[2 * k] * v[2 * k + 1] - x[2 * k + 1] * v[2 * k] +
                 (B ? B[4 * k + 2] - B[4 * k + 1] : 0.0));
  return L;
}

} // namespace gimp::transfer
