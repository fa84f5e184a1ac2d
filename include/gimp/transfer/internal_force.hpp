// Internal force of Eq. 8: f_i = - sum_p sigma_p . grad S_ip V_p, for any dimension D.
#pragma once

#include "gimp/grid/stencils.hpp"
#include "gimp/transfer/block_kernels.hpp"

namespace gimp::transfer {

/// Accumulates the internal force of particles k0 .. k1-1 into the window array f (D values per
/// slot). stress is the particles' symmetric Cauchy stress (kStress<D> entries each, stressAt), V
/// their current volumes.
template <int D>
void internalForce(const Stencils<D> &st, PetscInt k0, PetscInt k1, const double *V,
                   const double *stress, double *f) {
  for (PetscInt k = k0; k < k1; ++k) {
    const Tensor<D> A = -V[k] * stressAt<D>(stress, k);
    if constexpr (D == 2) { // f_ij = A (g_i w_j, w_i g_j), both components at once
      if (st.isBlock(k)) {
        blocks::internalForce(st.block(k), A, f);
        continue;
      }
      if (st.isBlock4(k)) {
        blocks::internalForce(st.block4(k), A, f);
        continue;
      }
    }
    st.forEach(k, [&](PetscInt nd, double, const Vector<D> &grad) {
      for (int c = 0; c < D; ++c) {
        double fc = 0.0;
        for (int a = 0; a < D; ++a)
          fc += A(c, a) * grad[a];
        f[D * nd + c] += fc;
      }
    });
  }
}

/// The same for every particle.
template <int D>
void internalForce(const Stencils<D> &st, PetscInt n, const double *V, const double *stress,
                   double *f) {
  internalForce<D>(st, 0, n, V, stress, f);
}

} // namespace gimp::transfer
