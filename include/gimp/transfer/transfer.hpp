// Particle <-> grid transfers as free kernels over explicit arrays, for any dimension D. They
// read the stencils through Stencils::forEach (rows or blocks alike).
//
// Nodal arrays are the window arrays of one rank: D values per slot (see grid/stencils.hpp);
// nodal mass is stored in component 0 of its slot, in the layout of the momentum. Particle
// arrays are those of a ParticleView. No kernel knows about PETSc objects, levels or ranks.
#pragma once

#include "gimp/grid/stencils.hpp"
#include "gimp/transfer/block_kernels.hpp"

namespace gimp::transfer {

/// P2G of particle k: S_ip m_p v_p into mom and, when mass is not null, S_ip m_p into component 0
/// of mass (accumulated).
template <int D>
GIMP_ALWAYS_INLINE void particleToGrid(const Stencils<D> &st, PetscInt k, double mp,
                                       const double *vk, double *mom, double *mass) {
  double pk[D];
  for (int c = 0; c < D; ++c)
    pk[c] = mp * vk[c];
  if constexpr (D == 2) { // sums along x for each row of nodes, both components at once
    if (st.isBlock(k)) return blocks::toGrid(st.block(k), mp, pk, mom, mass);
    if (st.isBlock4(k)) return blocks::toGrid(st.block4(k), mp, pk, mom, mass);
  }
  st.forEach(k, [&](PetscInt nd, double w, const Vector<D> &) {
    for (int c = 0; c < D; ++c)
      mom[D * nd + c] += w * pk[c];
    if (mass) mass[D * nd] += w * mp;
  });
}

/// P2G: nodal momentum sum_p S_ip m_p v_p into mom and, when mass is not null, nodal mass
/// sum_p S_ip m_p into component 0 of mass. Both are accumulated (the caller zeroes them).
template <int D>
void particlesToGrid(const Stencils<D> &st, PetscInt n, const double *m, const double *v,
                     double *mom, double *mass) {
  for (PetscInt k = 0; k < n; ++k)
    particleToGrid<D>(st, k, m[k], v + D * k, mom, mass);
}

/// The grid velocity vp and acceleration ap at particle k.
template <int D>
GIMP_ALWAYS_INLINE void particleFromGrid(const Stencils<D> &st, PetscInt k, const double *vg,
                                         const double *ag, double *vp, double *ap) {
  for (int c = 0; c < D; ++c)
    vp[c] = ap[c] = 0.0;
  if constexpr (D == 2) {
    if (st.isBlock(k)) return blocks::fromGrid(st.block(k), vg, ag, vp, ap);
    if (st.isBlock4(k)) return blocks::fromGrid(st.block4(k), vg, ag, vp, ap);
  }
  st.forEach(k, [&](PetscInt nd, double w, const Vector<D> &) {
    for (int c = 0; c < D; ++c) {
      vp[c] += w * vg[D * nd + c];
      ap[c] += w * ag[D * nd + c];
    }
  });
}

/// G2P of one rate class of a multi-rate step (docs/method.md, "Multi-rate time steps per
/// level"): v_p <- flip v_p + S u and x_p += dt S w, with u the class's velocity update field
/// (flip times its summed grid velocity increments plus (1 - flip) times the end velocity) and w
/// the mean grid velocity over its step dt. With mom, the new momenta are re-projected with the
/// same stencils (accumulated).
template <int D>
GIMP_ALWAYS_INLINE void particleFromGridRated(const Stencils<D> &st, PetscInt k, const double *ug,
                                              const double *wg, double dt, double flip,
                                              const double *m, double *v, double *x, double *mom) {
  double up[D], wp[D];
  particleFromGrid<D>(st, k, ug, wg, up, wp);
  for (int c = 0; c < D; ++c) {
    v[D * k + c] = flip * v[D * k + c] + up[c];
    x[D * k + c] += dt * wp[c];
  }
  if (mom) particleToGrid<D>(st, k, m[k], v + D * k, mom, nullptr);
}
template <int D>
void gridToParticlesRated(const Stencils<D> &st, PetscInt n, const double *ug, const double *wg,
                          double dt, double flip, const double *m, double *v, double *x,
                          double *mom) {
  for (PetscInt k = 0; k < n; ++k)
    particleFromGridRated<D>(st, k, ug, wg, dt, flip, m, v, x, mom);
}

/// The nodal field f at particle k: fp = sum_i S_ip f_i (D values).
template <int D>
GIMP_ALWAYS_INLINE void interpolateAt(const Stencils<D> &st, PetscInt k, const double *fg,
                                      double *fp) {
  for (int c = 0; c < D; ++c)
    fp[c] = 0.0;
  if constexpr (D == 2) {
    if (st.isBlock(k)) return blocks::interpolate(st.block(k), fg, fp);
    if (st.isBlock4(k)) return blocks::interpolate(st.block4(k), fg, fp);
  }
  st.forEach(k, [&](PetscInt nd, double w, const Vector<D> &) {
    for (int c = 0; c < D; ++c)
      fp[c] += w * fg[D * nd + c];
  });
}

/// G2P: each particle's velocity becomes flip (v + dt a_p) + (1 - flip) v_p with a_p and v_p
/// the grid acceleration and velocity at the particle, and it moves by dt v_p.
template <int D>
GIMP_ALWAYS_INLINE void particleFromGridFlip(const Stencils<D> &st, PetscInt k, const double *vg,
                                             const double *ag, double dt, double flip, double *v,
                                             double *x) {
  double vp[D], ap[D];
  particleFromGrid<D>(st, k, vg, ag, vp, ap);
  for (int c = 0; c < D; ++c) {
    v[D * k + c] = flip * (v[D * k + c] + dt * ap[c]) + (1.0 - flip) * vp[c];
    x[D * k + c] += dt * vp[c];
  }
}
template <int D>
void gridToParticles(const Stencils<D> &st, PetscInt n, const double *vg, const double *ag,
                     double dt, double flip, double *v, double *x) {
  for (PetscInt k = 0; k < n; ++k)
    particleFromGridFlip<D>(st, k, vg, ag, dt, flip, v, x);
}

/// G2P followed by the re-projection of the new momenta m_p v_p with the same stencils into mom
/// (accumulated), in one pass.
template <int D>
GIMP_ALWAYS_INLINE void particleFromGridProjected(const Stencils<D> &st, PetscInt k,
                                                  const double *vg, const double *ag, double dt,
                                                  double flip, const double *m, double *v,
                                                  double *x, double *mom) {
  if constexpr (D == 2) { // a block read once for both
    if (st.isBlock(k))
      return blocks::fromAndToGrid(st.block(k), vg, ag, dt, flip, m[k], v + 2 * k, x + 2 * k, mom);
    if (st.isBlock4(k))
      return blocks::fromAndToGrid(st.block4(k), vg, ag, dt, flip, m[k], v + 2 * k, x + 2 * k, mom);
  }
  particleFromGridFlip<D>(st, k, vg, ag, dt, flip, v, x);
  particleToGrid<D>(st, k, m[k], v + D * k, mom, nullptr);
}
template <int D>
void gridToParticlesProjected(const Stencils<D> &st, PetscInt n, const double *vg, const double *ag,
                              double dt, double flip, const double *m, double *v, double *x,
                              double *mom) {
  for (PetscInt k = 0; k < n; ++k)
    particleFromGridProjected<D>(st, k, vg, ag, dt, flip, m, v, x, mom);
}

/// Velocity gradient of particle k, L = sum_i v_i (x) grad S_ip.
template <int D>
GIMP_ALWAYS_INLINE Tensor<D> velocityGradientAt(const Stencils<D> &st, PetscInt k,
                                                const double *vg) {
  Tensor<D> Lk = Tensor<D>::Zero();
  if constexpr (D == 2) {
    if (st.isBlock(k)) return blocks::gradient(st.block(k), vg);
    if (st.isBlock4(k)) return blocks::gradient(st.block4(k), vg);
  }
  if constexpr (D == 3)
    if (st.isBlock(k)) { // rows along x: sum_i g_i v_c and sum_i w_i v_c, then the (y, z) factors
      const Block<3> b = st.block(k);
      for (int q = 0; q < 3; ++q)
        for (int j = 0; j < 3; ++j) {
          const PetscInt r = 3 * (b.base + j * b.stride[0] + q * b.stride[1]);
          double pg[3] = {0, 0, 0}, qw[3] = {0, 0, 0};
          for (int i = 0; i < 3; ++i)
            for (int c = 0; c < 3; ++c) {
              pg[c] += b.g[0][i] * vg[r + 3 * i + c];
              qw[c] += b.w[0][i] * vg[r + 3 * i + c];
            }
          const double wyz = b.w[1][j] * b.w[2][q], gy = b.g[1][j] * b.w[2][q],
                       gz = b.w[1][j] * b.g[2][q];
          for (int c = 0; c < 3; ++c) {
            Lk(c, 0) += wyz * pg[c];
            Lk(c, 1) += gy * qw[c];
            Lk(c, 2) += gz * qw[c];
          }
        }
      return Lk;
    }
  st.forEach(k, [&](PetscInt nd, double, const Vector<D> &grad) {
    for (int c = 0; c < D; ++c)
      for (int a = 0; a < D; ++a)
        Lk(c, a) += vg[D * nd + c] * grad[a];
  });
  return Lk;
}

/// Velocity gradient at each particle, row-major D x D per particle into L.
template <int D>
void velocityGradient(const Stencils<D> &st, PetscInt n, const double *vg, double *L) {
  for (PetscInt k = 0; k < n; ++k)
    tensorAt<D>(L, k) = velocityGradientAt<D>(st, k, vg);
}

} // namespace gimp::transfer
