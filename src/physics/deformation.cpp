#include "gimp/physics/deformation.hpp"

#include "gimp/core/pair.hpp"
#include "gimp/physics/material.hpp"
#include "gimp/physics/tracking.hpp"

namespace gimp::physics {

template <>
void updateDeformation<2>(const Scene<2> &sc, ParticleView<2> &p, const double *L, double dt,
                          PetscInt k0, PetscInt k1) {
  using simd::Pair;
  for (PetscInt k = k0; k < k1; ++k) {
    const Material &mat = sc.materialOf(p.id[k]);
    const Tensor<2> Lk = tensorAt<2>(L, k - k0);
    // F += dt L F row by row: each entry dt (L_i0 F_0j + L_i1 F_1j) added in that order.
    double *Fk = p.F + 4 * k;
    const Pair f0 = simd::load(Fk), f1 = simd::load(Fk + 2);
    const Pair n0 = f0 + dt * (Lk(0, 0) * f0 + Lk(0, 1) * f1);
    const Pair n1 = f1 + dt * (Lk(1, 0) * f0 + Lk(1, 1) * f1);
    simd::store(Fk, n0);
    simd::store(Fk + 2, n1);
    p.V[k] = (n0[0] * n1[1] - n0[1] * n1[0]) * p.V0[k];
    Tensor<2> s = stressAt<2>(p.s, k);
    if (mat.model == MaterialModel::Linear)
      material::jaumannUpdate(mat, Lk, dt, s, p.szz[k]);
    else
      material::neoHookeanStress(mat, tensorAt<2>(p.F, k), s, p.szz[k]);
    setStress<2>(p.s, k, s);
    tracking::updateDomain(sc, p, k, Lk, dt);
  }
}

template <>
void updateDeformation<3>(const Scene<3> &sc, ParticleView<3> &p, const double *L, double dt,
                          PetscInt k0, PetscInt k1) {
  for (PetscInt k = k0; k < k1; ++k) {
    const Material &mat = sc.materialOf(p.id[k]);
    const Tensor<3> Lk = tensorAt<3>(L, k - k0);
    auto F = tensorAt<3>(p.F, k);
    F += dt * product<3>(Lk, F);
    p.V[k] = determinant<3>(F) * p.V0[k];
    Tensor<3> s = stressAt<3>(p.s, k);
    if (mat.model == MaterialModel::Linear)
      material::jaumannUpdate(mat, Lk, dt, s);
    else
      material::neoHookeanStress(mat, Tensor<3>(F), s);
    setStress<3>(p.s, k, s);
    tracking::updateDomain<3>(sc, p, k, Lk, dt);
  }
}

} // namespace gimp::physics
