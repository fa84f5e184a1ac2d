// Energy and momentum of the particles, and the work ledger of external and damping forces.
#pragma once

#include "gimp/input/scene.hpp"

#include "gimp/particles/swarm.hpp"

#include <petscdm.h>

#include <vector>

namespace gimp {

struct Energies {
  double kinetic = 0, strain = 0, externalWork = 0, damping = 0;
  double momentum[3] = {0, 0, 0}; // the first D components
  double total() const { return kinetic + strain - externalWork + damping; }
};

/// Work of the external and damping forces over the run, each step's force times the mean of
/// the grid velocities at its start and end (see Solver::step).
struct WorkLedger {
  double external = 0, damping = 0;
  // The strain energy a report gives stands at the time of the particles' velocities, half a step
  // from their stresses (docs/method.md, *Energy balance*): it is the strain energy now plus
  // strainShift times the change of the last stress update (-1/2 when the stress is updated
  // after the grid update, +1/2 with USF). strainBefore holds, per rate class (one without
  // -gimp_multirate), this rank's strain energy of the class's particles before their last
  // update; it is measured on the steps that a report follows (measureStrain) and is empty
  // after the others, whose reports then give the strain energy now.
  double strainShift = -0.5;
  bool measureStrain = false;
  std::vector<double> strainBefore;
};

/// The strain energy of the particles of p (this rank's sum).
template <int D> double strainEnergySum(const Scene<D> &sc, const ParticleView<D> &p);

/// The ledger's strain energy before the last stress update, summed over the ranks (collective);
/// NaN when the last step did not measure it (WorkLedger::strainBefore empty on a rank).
PetscErrorCode strainBeforeTotal(MPI_Comm comm, const WorkLedger &work, double &sum);

/// Kinetic and strain energy and momentum of all particles (collective), with the ledger's work.
template <int D>
PetscErrorCode particleEnergies(MPI_Comm comm, const Scene<D> &sc, DM sw, const WorkLedger &work,
                                Energies &e);

} // namespace gimp
