// The particles' deformation update: F, volume, stress (material model) and domain (tracking)
// from the velocity gradient L over dt.
#pragma once

#include "gimp/input/scene.hpp"
#include "gimp/particles/swarm.hpp"

namespace gimp::physics {

/// F <- (I + dt L) F, V = det(F) V0, stress by the material model, domain by the tracking mode,
/// for particles k0 <= k < k1. L is row-major D x D per particle, L[D^2 (k - k0)] for particle k
/// (the solver passes a chunk of particles at a time). 2D: the rows of F as pairs and the
/// out-of-plane stress of plane strain; every tracking mode. 3D: the 3 x 3 materials; the
/// domain by none or stretch.
template <int D>
void updateDeformation(const Scene<D> &sc, ParticleView<D> &p, const double *L, double dt,
                       PetscInt k0, PetscInt k1);

} // namespace gimp::physics
