// Internal force of Eq. 8: f_i = - sum_p sigma_p . grad S_ip V_p, for any dimension D.
#pragma once

#include "gimp/grid/stencils.hpp"

namespace gimp::physics {

/// Accumulates the internal force into the window array f (D values per slot). stress is the
/// particles' row-major D x D Cauchy stress, V their current volumes.
template <int D>
void internalForce(const Stencils<D> &st, PetscInt n, const double *V, const double *stress,
                   double *f) {
  const PetscInt *start = st.start.data(), *node = st.node.data();
  for (PetscInt k = 0; k < n; ++k) {
    const Tensor<D> A = -V[k] * tensorAt<D>(stress, k);
    for (PetscInt e = start[k]; e < start[k + 1]; ++e) {
      const Vector<D> grad = st.gradient(e);
      const PetscInt nd = node[e];
      for (int c = 0; c < D; ++c) {
        double fc = 0.0;
        for (int a = 0; a < D; ++a)
          fc += A(c, a) * grad[a];
        f[D * nd + c] += fc;
      }
    }
  }
}

} // namespace gimp::physics
