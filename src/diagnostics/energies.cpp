#include "gimp/diagnostics/energies.hpp"

#include "gimp/particles/swarm.hpp"
#include "gimp/physics/material.hpp"

#include <cmath>
#include <limits>

namespace gimp {

namespace {

/// The strain energy of particle k (2D: with the out-of-plane stress).
double strainEnergyOf(const Scene<2> &sc, const ParticleView<2> &p, PetscInt k) {
  return material::strainEnergy(sc.materialOf(p.id[k]), stressAt<2>(p.s, k), p.szz[k],
                                tensorAt<2>(p.F, k), p.V0[k], p.V[k]);
}
double strainEnergyOf(const Scene<3> &sc, const ParticleView<3> &p, PetscInt k) {
  return material::strainEnergy(sc.materialOf(p.id[k]), stressAt<3>(p.s, k),
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

PetscErrorCode strainBeforeTotal(MPI_Comm comm, const WorkLedger &work, double &sum) {
  double mine[2] = {0, work.strainBefore.empty() ? 1.0 : 0.0}, all[2] = {};
  for (double b : work.strainBefore)
    mine[0] += b;
  PetscCallMPI(MPI_Allreduce(mine, all, 2, MPI_DOUBLE, MPI_SUM, comm));
  sum = all[1] == 0 ? all[0] : std::numeric_limits<double>::quiet_NaN();
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode particleEnergies(MPI_Comm comm, const Scene<D> &sc, DM sw, const WorkLedger &work,
                                Energies &e) {
  ParticleView<D> p;
  PetscCall(p.get(sw));
  double loc[2 + D] = {}, glob[2 + D];
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
  PetscCallMPI(MPI_Allreduce(loc, glob, 2 + D, MPI_DOUBLE, MPI_SUM, comm));
  e.kinetic = glob[0];
  double before = 0; // (NaN: not measured, the strain energy now)
  PetscCall(strainBeforeTotal(comm, work, before));
  e.strain = std::isnan(before) ? glob[1] : glob[1] + work.strainShift * (glob[1] - before);
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
