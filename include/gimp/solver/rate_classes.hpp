// The rate classes of -gimp_multirate (docs/method.md, "Multi-rate time steps per level"): the
// particles whose stencils reach level c at most form class c and step every levels[c].step
// fine steps. Each class keeps its stencils and, on the global grid, what it brought to the
// nodes at its start and what the nodes did since: the nodal step of solver/multirate.cpp.
#pragma once

#include "gimp/grid/grid.hpp"

#include <vector>

namespace gimp {

struct RateClasses {
  int n = 0;                      // classes: one per level
  std::vector<PetscInt> every;    // fine steps per step of class c (levels[c].step)
  std::vector<PetscInt> begin;    // class c holds this rank's particles [begin[c], begin[c + 1])
  std::vector<PetscInt64> size;   // particles of class c on all ranks (0: the class is skipped)
  std::vector<PetscInt> switched; // particles of class c that were in another class before
  std::vector<double> kickScale;  // per particle of this coarse step: its first kick's weight
                                  // over its class's step, (m_old + m_new) / (2 m_new)
  std::vector<Stencils<kDim>> st; // class c's stencils, from its last start
  std::vector<PetscInt> start;    // the sub-step of class c's last start
  std::vector<char> live; // a class stepping every sub-step: inc holds its increments (else dt a)
  // Global, per class (dof layout of the momentum): its mass (component 0) and momentum at its
  // start, the sum of the grid velocity increments and of the grid velocities since.
  std::vector<Vec> mass, mom, inc, vsum;
  // Node rule only, global, per class: its force at its last start (internal and external, times
  // that step's kick weight) and that force at the start of each node's anchor step (base); with
  // external forces the external part again, on its own, and its base.
  std::vector<Vec> force, base, fext, baseExt;
  // Node rule, global: each node's rate, the step of the slowest class whose mass is on it now
  // (its anchor; both dofs), set where a class starts (Solver::startClasses).
  Vec nodeRate = nullptr;
  Vec taken = nullptr, field = nullptr;  // global scratch: what the ending classes took, a field
  Vec corr = nullptr, corrSum = nullptr; // MUSL: a class's re-projection correction, their sum
  Vec fieldW = nullptr, meanW = nullptr, forceW = nullptr; // window scratch
  // With cracks, per class on the window: its crack faces from its start (Contact::faces; its
  // stencils and positions do not change until its end).
  std::vector<Vec> faces;

  RateClasses() = default;
  RateClasses(const RateClasses &) = delete;
  RateClasses &operator=(const RateClasses &) = delete;
  ~RateClasses();
  /// With `nodeRule` the vectors of -gimp_multirate_forces node (force, base, nodeRate, ...).
  PetscErrorCode create(const Grid<2> &grid, Vec like, bool external, bool nodeRule);
};

} // namespace gimp
