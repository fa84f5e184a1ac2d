// Filling the bodies with particles. Seeding is true geometry, one function per dimension:
// 2D (particles/seed.cpp) cuts each leaf cell into n x n squares, keeps the part of each square
// in the plane body (cut cells) and reads particle files; 3D (particles/seed_solid.cpp) cuts it
// into n^3 cubes kept by their centres. Both give ids that do not depend on the number of ranks
// (id / Scene::idSlots is the body) and mark the particles whose edges (2D) or faces (3D) lie on a
// loaded or constrained face of a body.
#pragma once

#include "gimp/grid/grid.hpp"
#include "gimp/input/scene.hpp"
#include "gimp/particles/swarm.hpp"

#include <string>
#include <vector>

namespace gimp {

/// What seeding finds wrong with the scene, refused on every rank alike by agree(). Two loads of
/// one kind on the same particle edge (2D) or face (3D) axis: a particle carries one traction and
/// one penalty condition per axis, so the second would replace the first (a body one particle
/// thick loaded on both sides, or overlapping ranges). In 3D, a particle centre that two bodies
/// hold (2D bodies are checked for overlap from their shapes at input).
struct LoadConflict {
  PetscInt64 code = -1; // kind << 40 | second << 20 | first of the smallest conflict (-1: none)
  int overlap = 0;      // the largest body index holding a centre an earlier body holds (0: none)
  /// kind 0: tractions, 1: penalty conditions; first was on the axis, second also matches.
  void note(int kind, PetscInt64 first, PetscInt64 second) {
    const PetscInt64 c = (PetscInt64{kind} << 40) | (second << 20) | first;
    if (code < 0 || c < code) code = c;
  }
  void noteOverlap(int body) { overlap = body > overlap ? body : overlap; }
  /// Collective: throws the same InputError on every rank when any rank noted a conflict.
  template <int D> PetscErrorCode agree(MPI_Comm comm, const Scene<D> &sc) const {
    std::vector<std::string> shapeOptions;
    for (const Body<D> &b : sc.bodies)
      shapeOptions.push_back(b.shapeOption);
    return agree(comm, shapeOptions);
  }
  /// The same, shapeOptions[b] naming the option that gave body b's shape (box, sphere, ...).
  PetscErrorCode agree(MPI_Comm comm, const std::vector<std::string> &shapeOptions) const;
};

/// Fill each body with particles (this rank's leaf cells), noting conflicting loads.
template <int D>
PetscErrorCode seedParticles(const Scene<D> &sc, const Grid<D> &grid, DM sw,
                             LoadConflict &conflict);

/// The seeded particles: every body holds some, every traction and penalty condition reaches a
/// particle edge (2D) or face (3D), every particle lies inside the grid (else InputError on every
/// rank). Returns the count and mean mass. Collective.
template <int D>
PetscErrorCode checkSeeding(MPI_Comm comm, const Scene<D> &sc, const Grid<D> &grid,
                            const ParticleView<D> &p, PetscInt64 &count, double &meanMass);

/// Id slots per body (see seedParticles).
template <int D> PetscInt64 bodyIdSlots(const Lattice<D> &grid);

} // namespace gimp
