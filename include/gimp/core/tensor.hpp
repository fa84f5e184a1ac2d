// Small fixed-size vectors and tensors of the kernels, and the one storage layout they share.
//
// Every per-particle tensor (deformation gradient F, velocity gradient L, Cauchy stress) is a
// D x D matrix stored row-major, D * D doubles per particle: entry (i, j) at i * D + j, so that
// for D = 2 the order is xx, xy, yx, yy with xy = d(.)_x / d y. Plane strain adds the
// out-of-plane stress szz as a separate scalar field (2D only). Kernels read and write the
// particle arrays through the Eigen maps below; nothing else indexes a tensor by hand.
#pragma once

#include <Eigen/Core>

/// For the per-particle pieces of the transfer kernels: one call per particle and phase, which
/// must be inlined into the particle loop (an out-of-line call per particle costs more than the
/// piece and keeps its stores from being scheduled with the loop's).
#if defined(__GNUC__)
#define GIMP_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define GIMP_ALWAYS_INLINE inline
#endif

namespace gimp {

/// The spatial dimension built today. Kernels take it as a template parameter (see
/// docs/architecture.md, "A 3D instantiation").
constexpr int kDim = 2;

template <int D> using Vector = Eigen::Matrix<double, D, 1>;
template <int D> using Tensor = Eigen::Matrix<double, D, D, Eigen::RowMajor>;

/// Particle k's tensor in an array of row-major D x D tensors.
template <int D> inline Eigen::Map<Tensor<D>> tensorAt(double *a, long k) {
  return Eigen::Map<Tensor<D>>(a + static_cast<long>(D) * D * k);
}
template <int D> inline Eigen::Map<const Tensor<D>> tensorAt(const double *a, long k) {
  return Eigen::Map<const Tensor<D>>(a + static_cast<long>(D) * D * k);
}
/// Particle k's vector in an array of D-vectors.
template <int D> inline Eigen::Map<Vector<D>> vectorAt(double *a, long k) {
  return Eigen::Map<Vector<D>>(a + static_cast<long>(D) * k);
}
template <int D> inline Eigen::Map<const Vector<D>> vectorAt(const double *a, long k) {
  return Eigen::Map<const Vector<D>>(a + static_cast<long>(D) * k);
}

/// A B with every entry summed in index order: results do not depend on which product kernel
/// Eigen picks for a fixed size (its kernels may sum in another order).
template <int D, class A, class B> inline Tensor<D> product(const A &a, const B &b) {
  Tensor<D> c;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) {
      double s = a(i, 0) * b(0, j);
      for (int k = 1; k < D; ++k)
        s += a(i, k) * b(k, j);
      c(i, j) = s;
    }
  return c;
}

/// det(F) of a D x D tensor: F_xx F_yy - F_xy F_yx in 2D, expanded along the first row in 3D (a
/// fixed summation order).
template <int D, class M> inline double determinant(const M &F) {
  if constexpr (D == 2)
    return F(0, 0) * F(1, 1) - F(0, 1) * F(1, 0);
  else
    return F(0, 0) * (F(1, 1) * F(2, 2) - F(1, 2) * F(2, 1)) -
           F(0, 1) * (F(1, 0) * F(2, 2) - F(1, 2) * F(2, 0)) +
           F(0, 2) * (F(1, 0) * F(2, 1) - F(1, 1) * F(2, 0));
}

} // namespace gimp
