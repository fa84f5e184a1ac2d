// The particles' deformation update: F, volume, stress (material model) and domain (tracking)
// from the velocity gradient L over dt.
#pragma once

#include "gimp/input/scene.hpp"
#include "gimp/particles/swarm.hpp"

namespace gimp::physics {

/// F <- (I + dt L) F, V = det(F) V0, stress by the material model, domain by the tracking mode,
/// for particles k0 <= k < k1. L is row-major 2 x 2 per particle, L[4 (k - k0)] for particle k
/// (the solver passes a chunk of particles at a time).
void updateDeformation(const Scene<2> &sc, ParticleView<2> &p, const double *L, double dt,
                       PetscInt k0, PetscInt k1);

} // namespace gimp::physics
