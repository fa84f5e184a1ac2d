// The size of a run estimated from the scene alone, before anything is allocated: grid nodes
// per level, particles per body, and the memory they take, refused with one line when it
// cannot fit (docs/validation.md, "Bad input and faults").
#pragma once

#include "gimp/input/scene.hpp"

namespace gimp {

/// What one particle and one grid node cost [bytes]; the solver knows its fields and vectors.
struct ItemBytes {
  double particle = 0, node = 0;
};

struct SizeEstimate {
  long double nodes = 0, particles = 0, bytes = 0;
  std::vector<long double> levelNodes, bodyParticles;
  std::vector<std::vector<long double>> levelAxes; // nodes along each axis per level
};

/// Nodes and particles the scene asks for, counted in long double (no overflow).
template <int D> SizeEstimate estimateSize(const Scene<D> &sc, const ItemBytes &cost);

/// Collective: throws InputError (every rank alike) when a level has more nodes than PetscInt
/// can index, a rank would hold more particles than PetscInt counts, or the estimate exceeds
/// -gimp_memory_limit (by default the physical memory of the nodes the ranks run on).
template <int D>
PetscErrorCode checkProblemSize(MPI_Comm comm, const Scene<D> &sc, const ItemBytes &cost);

} // namespace gimp
