// Splitting particles where a level box moved over them (levels that follow a point,
// solver/regrid.cpp; docs/method.md, *Levels that follow a point*): a particle seeded on a coarser
// level that now lies in a finer box becomes the particles that level would have seeded there.
#pragma once

#include "gimp/input/scene.hpp"

#include <petscdm.h>

#include <vector>

namespace gimp {

/// The ids split particles take: per body, counted down from the top of its id range
/// (Scene::idSlots), above every id seeding gave. Kept in checkpoints.
struct SplitIds {
  std::vector<PetscInt64> seededTop; // per body: the largest seeded id (set at the first split)
  std::vector<PetscInt64> used;      // per body: the ids split particles have taken
  PetscInt64 seeded = 0;             // the particles seeding gave (set at the first move; 0 before)
};

/// Every particle whose initial half-sizes are, along each axis, a whole multiple r_a of the
/// half-size of the particles the finest level holding its centre seeds (that level's cell over
/// the body's particles per cell along an axis), with some r_a >= 2, becomes prod r_a particles:
/// the r_a equal parts of its initial box along each axis, placed by F (or, with tracked corners,
/// by the bi/trilinear map of its corners, and given the parts of its corner cell), each with the
/// share 1 / prod r_a of its mass and volumes, and its velocity, affine moment B, F, stress and
/// strain (2D crack scenes' displacement us: the parent's, changed as x and X0 are). Mass,
/// momentum and the angular momentum sum m (x × v) + m ε:Bᵀ are kept to round-off;
/// the first part keeps the particle's id. Kept as they are: particles of a body read from a file,
/// cut-cell particles (a volume below their box's) and particles on a loaded face (a traction or
/// penalty condition acts on their edge). `added`: the particles added over all ranks.
/// Collective.
template <int D>
PetscErrorCode splitParticles(MPI_Comm comm, const Scene<D> &sc, DM sw, SplitIds &ids,
                              PetscInt64 &added);

/// The reverse, where a finer box moved away: the particles of one slot of the coarser particle
/// lattice now holding them (the parts a split of that slot's particle would give: prod r_a
/// particles of the same body and initial size, whose initial centres lie in the slot, all in one
/// level-0 cell now, no crack between them, none on a loaded face, none a cut cell) become one
/// particle: mass and volumes summed, position, initial position, velocity, F, strain and us
/// mass-weighted, stress volume-weighted, the slot's outer corners when corners are tracked, and
/// B = sum m_j (B_j + (v_j - v)(x_j - x)ᵀ) / m, which keeps APIC's angular momentum; the smallest
/// id stays. Mass, momentum and (with APIC) angular momentum are kept to round-off; the kinetic
/// energy of the parts' motion relative to their centre, ½ sum m_j |v_j - v|², goes into B's
/// affine field (APIC) or is lost (FLIP/PIC). A group that holds one of the particles `kept`
/// (the probes') is left as it is, so those particles keep their ids. `removed`: the particles
/// removed over all ranks. Collective.
template <int D>
PetscErrorCode mergeParticles(MPI_Comm comm, const Scene<D> &sc, DM sw,
                              const std::vector<PetscInt64> &kept, PetscInt64 &removed);

} // namespace gimp
