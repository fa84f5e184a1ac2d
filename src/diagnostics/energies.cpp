#include "gimp/diagnostics/energies.hpp"

#include "gimp/particles/swarm.hpp"
#include "gimp/physics/material.hpp"

namespace gimp {

PetscErrorCode particleEnergies(MPI_Comm comm, const Scene<2> &sc, DM sw, const WorkLedger &work,
                                Energies &e) {
  ParticleView<2> p;
  PetscCall(p.get(sw));
  double loc[4] = {0, 0, 0, 0}, glob[4];
  for (PetscInt k = 0; k < p.n; ++k) {
    const double vx = p.v[2 * k], vy = p.v[2 * k + 1];
    loc[0] += 0.5 * p.m[k] * (vx * vx + vy * vy);
    loc[1] += material::strainEnergy(sc.materialOf(p.id[k]), tensorAt<2>(p.s, k), p.szz[k],
                                     tensorAt<2>(p.F, k), p.V0[k], p.V[k]);
    loc[2] += p.m[k] * vx;
    loc[3] += p.m[k] * vy;
  }
  PetscCall(p.restore(sw));
  PetscCallMPI(MPI_Allreduce(loc, glob, 4, MPI_DOUBLE, MPI_SUM, comm));
  e.kinetic = glob[0];
  e.strain = glob[1];
  e.momentum[0] = glob[2];
  e.momentum[1] = glob[3];
  e.externalWork = work.external;
  e.damping = work.damping;
  return PETSC_SUCCESS;
}

} // namespace gimp
