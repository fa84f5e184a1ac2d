// Constitutive updates for one particle, on the tensor types of core/tensor.hpp (row-major
// D x D; the out-of-plane stress szz of the 2D models is a separate scalar).
#pragma once

#include "gimp/core/pair.hpp"
#include "gimp/core/tensor.hpp"
#include "gimp/input/scene.hpp"

namespace gimp::material {

/// Hypoelastic linear isotropic update with the Jaumann (co-rotational) rate over dt:
/// sigma += dt (lambda* tr(D) I + 2 mu D + W sigma - sigma W), D and W the symmetric and skew
/// parts of L. Plane strain carries szz += dt lambda tr(D); plane stress keeps szz = 0 with the
/// reduced lambda*. (Inline: it runs once per particle and step.)
inline void jaumannUpdate(const Material &m, const Tensor<2> &L, double dt, Eigen::Ref<Tensor<2>> s,
                          double &szz) {
  // Row by row as pairs, each entry the scalar expression
  // s += dt ((lambda* tr) I + 2 mu D + spin) in its order (D = (L + L^T) / 2).
  using simd::Pair;
  const Pair Lr0 = {L(0, 0), L(0, 1)}, Lr1 = {L(1, 0), L(1, 1)}; // rows of L and of L^T
  const Pair Lc0 = {L(0, 0), L(1, 0)}, Lc1 = {L(0, 1), L(1, 1)};
  const Pair D0 = 0.5 * (Lr0 + Lc0), D1 = 0.5 * (Lr1 + Lc1);
  const double w = 0.5 * (L(0, 1) - L(1, 0)); // W_xy
  const double tr = D0[0] + D1[1];
  // W sigma - sigma W for a symmetric sigma in 2D, in closed form.
  const double a = 2.0 * w * s(0, 1), b = w * (s(1, 1) - s(0, 0)), c = -2.0 * w * s(0, 1);
  const double lt = m.lambdaStar * tr, mu2 = 2.0 * m.mu;
  const Pair r0 = simd::load(&s(0, 0)), r1 = simd::load(&s(1, 0));
  simd::store(&s(0, 0), r0 + dt * (lt * Pair{1.0, 0.0} + mu2 * D0 + Pair{a, b}));
  simd::store(&s(1, 0), r1 + dt * (lt * Pair{0.0, 1.0} + mu2 * D1 + Pair{b, c}));
  if (m.planeStrain) szz += dt * m.lambda * tr;
}

/// Compressible neo-Hookean Cauchy stress from F (plane strain, Fzz = 1):
/// sigma = (lambda ln J I + mu (F F^T - I)) / J, szz = lambda ln J / J.
void neoHookeanStress(const Material &m, const Tensor<2> &F, Eigen::Ref<Tensor<2>> s, double &szz);

/// Stored elastic energy of a particle of reference volume V0 and current volume V.
/// Linear: the complementary energy sigma : C^-1 : sigma / 2 (frame independent);
/// neo-Hookean: the strain energy function.
double strainEnergy(const Material &m, const Tensor<2> &s, double szz, const Tensor<2> &F,
                    double V0, double V);

// The same in 3D (no out-of-plane component; lambda itself, never a plane-stress lambda*).

/// sigma += dt (lambda tr(D) I + 2 mu D + W sigma - sigma W), for a symmetric sigma (the result
/// is symmetric exactly).
void jaumannUpdate(const Material &m, const Tensor<3> &L, double dt, Eigen::Ref<Tensor<3>> s);

/// sigma = (lambda ln J I + mu (F F^T - I)) / J.
void neoHookeanStress(const Material &m, const Tensor<3> &F, Eigen::Ref<Tensor<3>> s);

/// Linear: ((1 + nu) sigma : sigma - nu tr(sigma)^2) V / (2 E); neo-Hookean:
/// V0 (mu (tr(F^T F) - 3) / 2 - mu ln J + lambda (ln J)^2 / 2).
double strainEnergy(const Material &m, const Tensor<3> &s, const Tensor<3> &F, double V0, double V);

} // namespace gimp::material
