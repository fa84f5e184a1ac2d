// Manufactured solutions used for convergence studies (docs/reference.md, section 2).
// AxialWave (-gimp_mms skb1d): u = A sin(2 pi X) cos(c pi t) along x, y and z at rest,
// neo-Hookean with nu = 0 (a 1D solution in a body of any dimension), on X in [0, 1].
#pragma once

#include "gimp/input/scene.hpp"

namespace gimp::mms {

struct AxialWave {
  double A = 0, c = 0;
  /// The scene's amplitude (-gimp_mms_amplitude) and material.
  template <int D>
  explicit AxialWave(const Scene<D> &sc) : AxialWave(sc.mmsAmplitude, sc.material) {}
  /// Amplitude A and the material (c = sqrt(E / rho)).
  AxialWave(double amplitude, const Material &m);
  double u(double X, double t) const;
  double F(double X, double t) const;         // dx/dX
  double bodyForce(double X, double t) const; // per unit mass
};

} // namespace gimp::mms
