// Manufactured solutions used for convergence studies (docs/reference.md, section 2).
// skb1d: u = A sin(2 pi X) cos(c pi t) along x, 1D neo-Hookean with nu = 0, on X in [0, 1].
#pragma once

#include "gimp/input/scene.hpp"

namespace gimp::mms {

struct Skb1d {
  double A = 0, c = 0;
  Skb1d(const Scene<2> &sc);
  /// Amplitude A and the material (c = sqrt(E / rho)), for a scene of any dimension.
  Skb1d(double amplitude, const Material &m);
  double u(double X, double t) const;
  double F(double X, double t) const;         // dx/dX
  double bodyForce(double X, double t) const; // per unit mass
};

} // namespace gimp::mms
