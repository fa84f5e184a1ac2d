// Filling the bodies with particles.
#pragma once

#include "gimp/grid/grid.hpp"
#include "gimp/particles/swarm.hpp"

namespace gimp {

/// Fill each body with particles: each leaf cell owned by this rank is cut into n x n squares
/// and the squares whose centre lies in the body become particles. Ids encode body, level, cell
/// and sub-cell, so they do not depend on the number of ranks; id / bodyIdSlots() is the body.
/// Particles on loaded sides get their traction and displacement-condition indices.
PetscErrorCode seedParticles(const Scene<2> &sc, const Grid<2> &grid, DM sw);

/// Two loads of one kind on the same particle edge (2D) or face (3D) axis: a particle carries one
/// traction and one penalty condition per axis, so the second would replace the first (a body
/// one particle thick loaded on both sides, or overlapping ranges). Seeding notes them; agree()
/// refuses the scene on every rank with one line.
struct LoadConflict {
  PetscInt64 code = -1; // kind << 40 | second << 20 | first of the smallest conflict (-1: none)
  /// kind 0: tractions, 1: penalty conditions; first was on the axis, second also matches.
  void note(int kind, PetscInt64 first, PetscInt64 second) {
    const PetscInt64 c = (PetscInt64{kind} << 40) | (second << 20) | first;
    if (code < 0 || c < code) code = c;
  }
  /// Collective: throws the same InputError on every rank when any rank noted a conflict.
  PetscErrorCode agree(MPI_Comm comm) const;
};

/// seedParticles, noting conflicting loads (the solver refuses them through LoadConflict::agree).
PetscErrorCode seedParticles(const Scene<2> &sc, const Grid<2> &grid, DM sw,
                             LoadConflict &conflict);

/// Id slots per body (see seedParticles).
PetscInt64 bodyIdSlots(const Lattice<2> &grid);

} // namespace gimp
