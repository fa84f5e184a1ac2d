// Constitutive updates for one particle. Stress is stored as (sxx, syy, sxy, szz);
// the velocity gradient L as (Lxx, Lxy, Lyx, Lyy) with Lxy = d vx / d y; F likewise.
#pragma once

#include "gimp/scene.hpp"

namespace gimp::material {

/// Hypoelastic linear isotropic update with the Jaumann (co-rotational) rate over dt:
/// sigma += dt (lambda* tr(D) I + 2 mu D + W sigma - sigma W). Plane strain carries szz =
/// lambda (exx + eyy); plane stress keeps szz = 0 with the reduced lambda*.
void jaumannUpdate(const Material &m, const double L[4], double dt, double s[4]);

/// Compressible neo-Hookean Cauchy stress from F (plane strain, Fzz = 1):
/// sigma = (lambda ln J I + mu (F F^T - I)) / J.
void neoHookeanStress(const Material &m, const double F[4], double s[4]);

/// Stored elastic energy of a particle of reference volume V0 and current volume V.
/// Linear: the complementary energy sigma : C^-1 : sigma / 2 (frame independent);
/// neo-Hookean: the strain energy function.
double strainEnergy(const Material &m, const double s[4], const double F[4], double V0, double V);

} // namespace gimp::material
