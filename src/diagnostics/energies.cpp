#include "gimp/diagnostics/energies.hpp"

#include "gimp/particles/swarm.hpp"
#include "gimp/physics/material.hpp"

namespace gimp {

namespace {

/// The strain energy of particle k (2D: with the out-of-plane stress).
double strainEnergyOf(const Scene<2> &sc, const ParticleView<2> &p, PetscInt k) {
  return material::strainEnergy(sc.materialOf(p.id[k]), tensorAt<2>(p.s, k), p.szz[k],
                                tensorAt<2>(p.F, k), p.V0[k], p.V[k]);
}
double strainEnergyOf(const Scene<3> &sc, const ParticleView<3> &p, PetscInt k) {
  return material::strainEnergy(sc.materialOf(p.id[k]), Tensor<3>(tensorAt<3>(p.s, k)),
                                Tensor<3>(tensorAt<3>(p.F, k)), p.V0[k], p.V[k]);
}

} // namespace

template <int D> double strainEnergySum(const Scene<D> &sc, const ParticleView<D> &p) {
  double sum = 0;
  for (PetscInt k = 0; k < p.n; ++k)
    sum += strainEnergyOf(sc, p, k);
  return sum;
}
template double strainEnergySum<2>(const Scene<2> &, const ParticleView<2> &);
template double strainEnergySum<3>(const Scene<3> &, const ParticleView<3> &);

template <int D>
PetscErrorCode particleEnergies(MPI_Comm comm, const Scene<D> &sc, DM sw, const WorkLedger &work,
                                Energies &e) {
  ParticleView<D> p;
  PetscCall(p.get(sw));
  // (after the momentum: the strain energy before the last update and whether it was measured)
  double loc[4 + D] = {}, glob[4 + D];
  for (double b : work.strainBefore)
    loc[2 + D] += b;
  loc[3 + D] = work.strainBefore.empty() ? 0.0 : 1.0;
  for (PetscInt k = 0; k < p.n; ++k) {
    double v2 = 0;
    for (int a = 0; a < D; ++a)
      v2 += p.v[D * k + a] * p.v[D * k + a];
    loc[0] += 0.5 * p.m[k] * v2;
    loc[1] += strainEnergyOf(sc, p, k);
    for (int a = 0; a < D; ++a)
      loc[2 + a] += p.m[k] * p.v[D * k + a];
  }
  PetscCall(p.restore(sw));
  PetscCallMPI(MPI_Allreduce(loc, glob, 4 + D, MPI_DOUBLE, MPI_SUM, comm));
  e.kinetic = glob[0];
  PetscMPIInt ranks = 1;
  PetscCallMPI(MPI_Comm_size(comm, &ranks));
  const bool measured = glob[3 + D] == static_cast<double>(ranks);
  e.strain = measured ? glob[1] + work.strainShift * (glob[1] - glob[2 + D]) : glob[1];
  for (int a = 0; a < D; ++a)
    e.momentum[a] = glob[2 + a];
  e.externalWork = work.external;
  e.damping = work.damping;
  return PETSC_SUCCESS;
}

template PetscErrorCode particleEnergies<2>(MPI_Comm, const Scene<2> &, DM, const WorkLedger &,
                                            Energies &);
template PetscErrorCode particleEnergies<3>(MPI_Comm, const Scene<3> &, DM, const WorkLedger &,
                                            Energies &);

} // namespace gimp
