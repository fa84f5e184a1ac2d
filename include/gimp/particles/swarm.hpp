// Material points in a PETSc DMSwarm (structure of arrays).
//
// One table, particleFields(), lists every field once: its name, components, type, whether the
// HDF5 output writes it and whether it exists only with corner tracking. Registration,
// ParticleView::get/restore and the output all walk that table. A ParticleView borrows every
// field's array for one phase of a step; restore() hands them back to the swarm.
#pragma once

#include "gimp/core/petsc_compat.hpp"
#include "gimp/core/tensor.hpp"

#include <petscdmswarm.h>

#include <vector>

namespace gimp {

struct ParticleView {
  static constexpr int D = kDim;
  PetscInt n = 0;
  double *x = nullptr;       // position [D]
  double *X0 = nullptr;      // initial position [D]
  double *v = nullptr;       // velocity [D]
  double *m = nullptr;       // mass
  double *V0 = nullptr;      // initial volume (area x thickness)
  double *V = nullptr;       // current volume
  double *l = nullptr;       // current half-sizes [D]
  double *l0 = nullptr;      // initial half-sizes [D]
  double *F = nullptr;       // deformation gradient, row-major D x D
  double *s = nullptr;       // Cauchy stress, row-major D x D
  double *szz = nullptr;     // out-of-plane stress (plane strain; zero in plane stress)
  double *eps = nullptr;     // accumulated small-strain increments (xx, yy) [D]
  double *B = nullptr;       // APIC affine moment sum_i S_ip v_i (x_i - x_p)^T, row-major D x D
  PetscInt64 *id = nullptr;  // identity, independent of the rank count
  PetscInt *trac = nullptr;  // traction index on its x side and y side, -1 if none [D]
  PetscInt *dbc = nullptr;   // penalty displacement condition index, likewise [D]
  double *corners = nullptr; // tracked corners (-,-), (+,-), (+,+), (-,+) [2^D x D], if any
  PetscInt *rank = nullptr;  // owner rank (DMSwarm's migration field)
  bool hasCorners = false;   // the swarm carries the corners field (found by get())

  PetscErrorCode get(DM sw);
  PetscErrorCode restore(DM sw);
};

struct FieldSpec {
  const char *name;
  PetscInt components;
  PetscDataType type;
  bool written;     // in the HDF5 particle output
  bool cornersOnly; // registered only with corner tracking
  void **(*slot)(ParticleView &);
};

/// Every particle field, in registration order.
const std::vector<FieldSpec> &particleFields();

/// Create the swarm with gimp's fields (collective).
PetscErrorCode createSwarm(MPI_Comm comm, bool corners, DM *sw);

/// Whether the swarm carries the corner field.
PetscErrorCode swarmHasCorners(DM sw, bool &has);

} // namespace gimp
