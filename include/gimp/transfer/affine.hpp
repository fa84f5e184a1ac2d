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
    for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e)
      for (int a = 0; a < D; ++a)
        c[a] += st.weight(e) * xs[D * st.node[e] + a];
    for (int a = 0; a < D; ++a)
      xc[D * k + a] = c[a];
  }
}

/// D_p = sum_i S_ip (x_i - x_p)(x_i - x_p)^T of particle k.
template <int D>
Tensor<D> inertia(const Stencils<D> &st, PetscInt k, const double *xc, const double *xs) {
  Tensor<D> Dp = Tensor<D>::Zero();
  for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e) {
    const double w = st.weight(e);
    const PetscInt nd = st.node[e];
    double dx[D];
    for (int a = 0; a < D; ++a)
      dx[a] = xs[D * nd + a] - xc[D * k + a];
    for (int a = 0; a < D; ++a)
      for (int b = 0; b < D; ++b)
        Dp(a, b) += w * dx[a] * dx[b];
  }
  return Dp;
}

/// D_p^-1 of particle k. Where D_p is singular (its determinant below 1e-12 of (trace / D)^D: a
/// particle whose weights all sit on one line of nodes) the inverse is taken as 0, so C_p = 0
/// and the particle transfers as in PIC.
template <int D>
Tensor<D> inverseInertia(const Stencils<D> &st, PetscInt k, const double *xc, const double *xs) {
  const Tensor<D> Dp = inertia<D>(st, k, xc, xs);
  const double scale = std::pow(Dp.trace() / D, D);
  if (!(Dp.determinant() > 1e-12 * scale)) return Tensor<D>::Zero();
  return Dp.inverse();
}

/// D_p^-1 for every particle (row-major D x D into Dinv). It depends on the stencils only: the
/// solver computes it once per step for P2G and the re-projection.
template <int D>
void inverseInertias(const Stencils<D> &st, PetscInt n, const double *xc, const double *xs,
                     double *Dinv) {
  for (PetscInt k = 0; k < n; ++k)
    tensorAt<D>(Dinv, k) = inverseInertia<D>(st, k, xc, xs);
}

/// C_p = B_p D_p^-1 for every particle from the inverses of inverseInertias.
template <int D>
void affineFromInverse(PetscInt n, const double *B, const double *Dinv, double *C) {
  for (PetscInt k = 0; k < n; ++k)
    tensorAt<D>(C, k) = product<D>(tensorAt<D>(B, k), tensorAt<D>(Dinv, k));
}

/// C_p = B_p D_p^-1 for every particle (row-major D x D into C).
template <int D>
void affineVelocity(const Stencils<D> &st, PetscInt n, const double *xc, const double *xs,
                    const double *B, double *C) {
  for (PetscInt k = 0; k < n; ++k)
    tensorAt<D>(C, k) = product<D>(tensorAt<D>(B, k), inverseInertia<D>(st, k, xc, xs));
}

/// APIC P2G: nodal momentum sum_p S_ip m_p (v_p + C_p (x_i - x_p)) into mom and, when mass is
/// not null, nodal mass sum_p S_ip m_p into component 0 of mass (both accumulated).
template <int D>
void particlesToGridAffine(const Stencils<D> &st, PetscInt n, const double *m, const double *v,
                           const double *C, const double *xc, const double *xs, double *mom,
                           double *mass) {
  for (PetscInt k = 0; k < n; ++k) {
    const double mp = m[k];
    const auto Ck = tensorAt<D>(C, k);
    for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e) {
      const double w = st.weight(e);
      const PetscInt nd = st.node[e];
      double dx[D];
      for (int a = 0; a < D; ++a)
        dx[a] = xs[D * nd + a] - xc[D * k + a];
      for (int c = 0; c < D; ++c) {
        double vc = v[D * k + c];
        for (int a = 0; a < D; ++a)
          vc += Ck(c, a) * dx[a];
        mom[D * nd + c] += w * mp * vc;
      }
      if (mass) mass[D * nd] += w * mp;
    }
  }
}

/// APIC G2P: v_p = sum_i S_ip v_i, B_p = sum_i S_ip v_i (x_i - x_p)^T, and the particle moves by
/// dt v_p. x may be the array xc points to: each particle reads its own centre before it moves.
template <int D>
void gridToParticlesAffine(const Stencils<D> &st, PetscInt n, const double *vg, const double *xc,
                           const double *xs, double dt, double *v, double *B, double *x) {
  for (PetscInt k = 0; k < n; ++k) {
    double vp[D] = {};
    Tensor<D> Bk = Tensor<D>::Zero();
    for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e) {
      const double w = st.weight(e);
      const PetscInt nd = st.node[e];
      for (int c = 0; c < D; ++c) {
        const double wv = w * vg[D * nd + c];
        vp[c] += wv;
        for (int a = 0; a < D; ++a)
          Bk(c, a) += wv * (xs[D * nd + a] - xc[D * k + a]);
      }
    }
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
    for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e) {
      const double w = st.weight(e);
      for (int c = 0; c < D; ++c)
        fp[c] += w * fg[D * st.node[e] + c];
    }
    for (int c = 0; c < D; ++c)
      out[D * k + c] = fp[c];
  }
}

/// XPIC(m) G2P: v_p = sum_i S_ip (v*_i + dt a_i) with v* the filtered start velocity of the
/// step, and the particle moves by dt sum_i S_ip v_i (v the updated grid velocity).
template <int D>
void gridToParticlesFiltered(const Stencils<D> &st, PetscInt n, const double *vg, const double *ag,
                             const double *vstar, double dt, double *v, double *x) {
  for (PetscInt k = 0; k < n; ++k) {
    double vp[D] = {}, up[D] = {};
    for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e) {
      const double w = st.weight(e);
      const PetscInt nd = st.node[e];
      for (int c = 0; c < D; ++c) {
        vp[c] += w * vg[D * nd + c];
        up[c] += w * (vstar[D * nd + c] + dt * ag[D * nd + c]);
      }
    }
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
