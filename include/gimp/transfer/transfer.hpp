// Particle <-> grid transfers as free kernels over explicit arrays, for any dimension D.
//
// Nodal arrays are the window arrays of one rank: D values per slot (see grid/stencils.hpp);
// nodal mass is stored in component 0 of its slot, in the layout of the momentum. Particle
// arrays are those of a ParticleView. No kernel knows about PETSc objects, levels or ranks.
#pragma once

#include "gimp/grid/stencils.hpp"

namespace gimp::transfer {

/// P2G: nodal momentum sum_p S_ip m_p v_p into mom and, when mass is not null, nodal mass
/// sum_p S_ip m_p into component 0 of mass. Both are accumulated (the caller zeroes them).
template <int D>
void particlesToGrid(const Stencils<D> &st, PetscInt n, const double *m, const double *v,
                     double *mom, double *mass) {
  const PetscInt *start = st.start.data(), *node = st.node.data();
  for (PetscInt k = 0; k < n; ++k) {
    const double mp = m[k];
    double pk[D];
    for (int c = 0; c < D; ++c)
      pk[c] = mp * v[D * k + c];
    for (PetscInt e = start[k]; e < start[k + 1]; ++e) {
      const double w = st.weight(e);
      const PetscInt nd = node[e];
      for (int c = 0; c < D; ++c)
        mom[D * nd + c] += w * pk[c];
      if (mass) mass[D * nd] += w * mp;
    }
  }
}

/// G2P: each particle's velocity becomes flip (v + dt a_p) + (1 - flip) v_p with a_p and v_p
/// the grid acceleration and velocity at the particle, and it moves by dt v_p.
template <int D>
void gridToParticles(const Stencils<D> &st, PetscInt n, const double *vg, const double *ag,
                     double dt, double flip, double *v, double *x) {
  const PetscInt *start = st.start.data(), *node = st.node.data();
  for (PetscInt k = 0; k < n; ++k) {
    double vp[D] = {}, ap[D] = {};
    for (PetscInt e = start[k]; e < start[k + 1]; ++e) {
      const double w = st.weight(e);
      const PetscInt nd = node[e];
      for (int c = 0; c < D; ++c) {
        vp[c] += w * vg[D * nd + c];
        ap[c] += w * ag[D * nd + c];
      }
    }
    for (int c = 0; c < D; ++c) {
      v[D * k + c] = flip * (v[D * k + c] + dt * ap[c]) + (1.0 - flip) * vp[c];
      x[D * k + c] += dt * vp[c];
    }
  }
}

/// Velocity gradient at each particle, L = sum_i v_i (x) grad S_ip, row-major D x D per
/// particle into L.
template <int D>
void velocityGradient(const Stencils<D> &st, PetscInt n, const double *vg, double *L) {
  const PetscInt *start = st.start.data(), *node = st.node.data();
  for (PetscInt k = 0; k < n; ++k) {
    Tensor<D> Lk = Tensor<D>::Zero();
    for (PetscInt e = start[k]; e < start[k + 1]; ++e) {
      const Vector<D> grad = st.gradient(e);
      const PetscInt nd = node[e];
      for (int c = 0; c < D; ++c)
        for (int a = 0; a < D; ++a)
          Lk(c, a) += vg[D * nd + c] * grad[a];
    }
    tensorAt<D>(L, k) = Lk;
  }
}

} // namespace gimp::transfer
