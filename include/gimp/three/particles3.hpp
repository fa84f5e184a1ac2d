// The material points of a 3D run in a PETSc DMSwarm (structure of arrays), and their seeding.
// The fields are those of the 2D swarm (particles/swarm.hpp) with three components, less what
// only 2D scenes use (szz, eps, corners, the multi-rate class).
#pragma once

#include "gimp/core/tensor.hpp"
#include "gimp/grid/grid.hpp"
#include "gimp/input/scene.hpp"

#include <petscdmswarm.h>

#include <vector>

namespace gimp {
struct LoadConflict;
}

namespace gimp::three {

struct Particles3 {
  static constexpr int D = 3;
  PetscInt n = 0;
  double *x = nullptr, *X0 = nullptr, *v = nullptr; // [3]
  double *m = nullptr, *V0 = nullptr, *V = nullptr;
  double *l = nullptr, *l0 = nullptr; // half-sizes [3]
  double *F = nullptr, *s = nullptr;  // row-major 3 x 3
  double *B = nullptr;                // APIC's affine moment, if APIC
  PetscInt64 *id = nullptr;
  PetscInt *trac = nullptr, *dbc = nullptr; // per axis: the traction / penalty condition on the
                                            // particle's face normal to it, -1 if none [3]
  PetscInt *rank = nullptr;
  bool affine = false, boundary = false;

  PetscErrorCode get(DM sw);
  PetscErrorCode restore(DM sw);
};

/// Reorder this rank's particles: particle k becomes the former particle order[k] (not
/// collective).
PetscErrorCode permuteSwarm3(DM sw, const std::vector<PetscInt> &order);

/// Create the 3D swarm with the fields the scene needs (collective).
PetscErrorCode createSwarm3(MPI_Comm comm, const Scene<3> &sc, DM *sw);

/// Fill the swarm: n^3 particles per leaf cell of the composite grid (the finest level covering
/// the cell's centre), each kept when its centre is inside a body (a box, sphere or cylinder, not
/// in a hole); this rank seeds the leaf cells whose centre lies in its own level-0 cells. Ids are
/// body * idSlots plus the particle's index in a numbering that every rank count shares.
/// `overlapping` is the largest index of a body with a particle centre that an earlier body also
/// holds on this rank (0: none); `conflict` notes two loads of one kind on one particle face axis.
PetscErrorCode seedParticles3(const Scene<3> &sc, const Grid<3> &grid, PetscMPIInt rank, DM sw,
                              int &overlapping, LoadConflict &conflict);

} // namespace gimp::three
