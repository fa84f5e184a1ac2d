#include "gimp/physics/deformation.hpp"

#include "gimp/physics/material.hpp"
#include "gimp/physics/tracking.hpp"

namespace gimp::physics {

void updateDeformation(const Scene &sc, ParticleView &p, const double *L, double dt, PetscInt k0,
                       PetscInt k1) {
  for (PetscInt k = k0; k < k1; ++k) {
    const Material &mat = sc.materialOf(p.id[k]);
    const Tensor<2> Lk = tensorAt<2>(L, k - k0);
    auto F = tensorAt<2>(p.F, k);
    F += dt * product<2>(Lk, F);
    p.V[k] = determinant2(F) * p.V0[k];
    if (mat.model == MaterialModel::Linear)
      material::jaumannUpdate(mat, Lk, dt, tensorAt<2>(p.s, k), p.szz[k]);
    else
      material::neoHookeanStress(mat, F, tensorAt<2>(p.s, k), p.szz[k]);
    tracking::updateDomain(sc, p, k, Lk, dt);
  }
}

} // namespace gimp::physics
