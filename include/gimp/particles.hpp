// Material points in a PETSc DMSwarm (structure of arrays). ParticleView borrows every
// field's array for one phase of a step; restore() hands them back to the swarm.
#pragma once

#include "gimp/grid.hpp"
#include "gimp/scene.hpp"

#include <petscdmswarm.h>

namespace gimp {

struct ParticleView {
  PetscInt n = 0;
  double *x = nullptr;   // position [2]
  double *X0 = nullptr;  // initial position [2]
  double *v = nullptr;   // velocity [2]
  double *m = nullptr;   // mass
  double *V0 = nullptr;  // initial volume (area x thickness)
  double *V = nullptr;   // current volume
  double *l = nullptr;   // current half-sizes [2]
  double *l0 = nullptr;  // initial half-sizes [2]
  double *F = nullptr;   // deformation gradient (xx, xy, yx, yy) [4]
  double *s = nullptr;   // Cauchy stress (xx, yy, xy, zz) [4]
  double *eps = nullptr; // accumulated small-strain increments (xx, yy) [2]
  PetscInt64 *id = nullptr;
  PetscInt *trac = nullptr;  // traction index on its x side and y side, -1 if none [2]
  PetscInt *dbc = nullptr;   // penalty displacement condition index, likewise [2]
  double *corners = nullptr; // tracked corners (-,-), (+,-), (+,+), (-,+) as x,y [8], if any
  bool hasCorners = false;   // the swarm carries the corners field (found by get())
  PetscInt *rank = nullptr;  // owner rank (DMSwarm's migration field)

  PetscErrorCode get(DM sw);
  PetscErrorCode restore(DM sw);
};

/// Create the swarm with gimp's fields (collective).
PetscErrorCode createSwarm(MPI_Comm comm, bool corners, DM *sw);

/// Fill each body with particles: each cell owned by this rank is cut into n x n squares and
/// the squares whose centre lies in the body become particles. Ids do not depend on the
/// number of ranks. Particles on loaded sides get their traction index.
PetscErrorCode seedParticles(const Scene &sc, const Grid &grid, DM sw);

} // namespace gimp
