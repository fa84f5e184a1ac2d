// Small fixed-size vectors and tensors of the kernels, and the one storage layout they share.
//
// A per-particle tensor (deformation gradient F, velocity gradient L, APIC's B) is a D x D
// matrix stored row-major, D * D doubles per particle: entry (i, j) at i * D + j, so that for
// D = 2 the order is xx, xy, yx, yy with xy = d(.)_x / d y. The Cauchy stress is symmetric and
// keeps its D (D + 1) / 2 distinct entries (kStress), in Voigt order: 2D xx, yy, xy; 3D xx, yy,
// zz, yz, xz, xy (stressAt, setStress). Plane strain adds the out-of-plane stress szz as a
// separate scalar field (2D only). Kernels read and write the particle arrays through the
// accessors below; nothing else indexes a tensor by hand.
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
/// Entries per particle of a symmetric stress: 3 in 2D, 6 in 3D.
template <int D> constexpr int kStress = (D * (D + 1)) / 2;
/// The row and column of Voigt entry c (kStress<D> of them): the diagonal, then the
/// off-diagonal entries (2D: xy; 3D: yz, xz, xy).
template <int D> constexpr int voigtRow(int c) {
  return c < D ? c : D == 2 ? 0 : c == 3 ? 1 : 0;
}
template <int D> constexpr int voigtCol(int c) {
  return c < D ? c : D == 2 ? 1 : c == 3 ? 2 : c == 4 ? 2 : 1;
}
/// Particle k's stress as a full (symmetric) D x D tensor, from an array of kStress<D> entries
/// per particle.
template <int D> inline Tensor<D> stressAt(const double *a, long k) {
  const double *e = a + static_cast<long>(kStress<D>) * k;
  Tensor<D> s;
  for (int c = 0; c < kStress<D>; ++c)
    s(voigtRow<D>(c), voigtCol<D>(c)) = s(voigtCol<D>(c), voigtRow<D>(c)) = e[c];
  return s;
}
/// Stores a symmetric tensor s as particle k's stress (its upper triangle; the stress updates
/// give both triangles the same values exactly).
template <int D, class M> inline void setStress(double *a, long k, const M &s) {
  double *e = a + static_cast<long>(kStress<D>) * k;
  for (int c = 0; c < kStress<D>; ++c)
    e[c] = s(voigtRow<D>(c), voigtCol<D>(c));
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
