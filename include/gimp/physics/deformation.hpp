// The particles' deformation update: F, volume, stress (material model) and domain (tracking)
// from the velocity gradient L over dt.
#pragma once

#include "gimp/input/scene.hpp"
#include "gimp/particles/swarm.hpp"

namespace gimp::physics {

/// F <- (I + dt L) F, V = det(F) V0, stress by the material model, domain by the tracking mode.
/// L is row-major 2 x 2 per particle.
void updateDeformation(const Scene &sc, ParticleView &p, const double *L, double dt);

} // namespace gimp::physics
