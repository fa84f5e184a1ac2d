// Internal force of Eq. 8: f_i = - sum_p sigma_p . grad S_ip V_p, for any dimension D.
#pragma once

#include "gimp/grid/stencils.hpp"

namespace gimp::physics {

/// Accumulates the internal force into the window array f (D values per slot). stress is the
/// particles' row-major D x D Cauchy stress, V their current volumes.
template <int D>
void internalForce(const Stencils<D> &st, PetscInt n, const double *V, const double *stress,
                   double *f) {
  for (PetscInt k = 0; k < n; ++k) {
    const Tensor<D> A = -V[k] * tensorAt<D>(stress, k);
    if constexpr (D == 2)
      if (st.isBlock(k)) {              // f_ij = A (g_i w_j, w_i g_j)
        const Block<2> b = st.block(k); // a copy: stores to nodal arrays cannot alias it
        for (int j = 0; j < 3; ++j) {
          double *row = f + 2 * (b.base + j * b.stride[0]);
          const double a0 = A(0, 0) * b.w[1][j], a1 = A(1, 0) * b.w[1][j];
          const double c0 = A(0, 1) * b.g[1][j], c1 = A(1, 1) * b.g[1][j];
          for (int i = 0; i < 3; ++i) {
            row[2 * i] += b.g[0][i] * a0 + b.w[0][i] * c0;
            row[2 * i + 1] += b.g[0][i] * a1 + b.w[0][i] * c1;
          }
        }
        continue;
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

} // namespace gimp::physics
