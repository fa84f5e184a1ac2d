// Filling the bodies with particles.
#pragma once

#include "gimp/grid/grid.hpp"
#include "gimp/particles/swarm.hpp"

namespace gimp {

/// Fill each body with particles: each leaf cell owned by this rank is cut into n x n squares
/// and the squares whose centre lies in the body become particles. Ids encode body, level, cell
/// and sub-cell, so they do not depend on the number of ranks; id / bodyIdSlots() is the body.
/// Particles on loaded sides get their traction and displacement-condition indices.
PetscErrorCode seedParticles(const Scene &sc, const Grid &grid, DM sw);

/// Id slots per body (see seedParticles).
PetscInt64 bodyIdSlots(const Lattice &grid);

} // namespace gimp
