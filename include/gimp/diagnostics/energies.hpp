// Energy and momentum of the particles, and the work ledger of external and damping forces.
#pragma once

#include "gimp/input/scene.hpp"

#include <petscdm.h>

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
};

/// Kinetic and strain energy and momentum of all particles (collective), with the ledger's work.
template <int D>
PetscErrorCode particleEnergies(MPI_Comm comm, const Scene<D> &sc, DM sw, const WorkLedger &work,
                                Energies &e);

} // namespace gimp
