// Internal force of Eq. 8: f_i = - sum_p sigma_p . grad S_ip V_p, for any dimension D.
#pragma once

#include "gimp/core/pair.hpp"
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
      if (st.isBlock(k)) { // f_ij = A (g_i w_j, w_i g_j), both components at once
        using simd::Pair;
        const Block<2> &b = st.block(k);
        // Everything read before the first store (which the compiler cannot tell from b).
        const Pair A0 = {A(0, 0), A(1, 0)}, A1 = {A(0, 1), A(1, 1)};
        Pair gx[3], wx[3], a[3], c[3];
        PetscInt row[3];
        for (int i = 0; i < 3; ++i) {
          gx[i] = simd::splat(b.g[0][i]);
          wx[i] = simd::splat(b.w[0][i]);
          a[i] = A0 * b.w[1][i];
          c[i] = A1 * b.g[1][i];
          row[i] = 2 * (b.base + i * b.stride[0]);
        }
        for (int j = 0; j < 3; ++j)
          for (int i = 0; i < 3; ++i)
            simd::addTo(f + row[j] + 2 * i, gx[i] * a[j] + wx[i] * c[j]);
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
