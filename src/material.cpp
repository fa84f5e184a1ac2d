#include "gimp/material.hpp"

#include <cmath>

namespace gimp::material {

void jaumannUpdate(const Material &m, const double L[4], double dt, double s[4]) {
  const double dxx = L[0], dyy = L[3], dxy = 0.5 * (L[1] + L[2]);
  const double w = 0.5 * (L[1] - L[2]); // W_xy
  const double lam = m.lambdaStar, mu2 = 2.0 * m.mu;
  const double tr = dxx + dyy;
  const double sxx = s[0], syy = s[1], sxy = s[2];
  s[0] = sxx + dt * (lam * tr + mu2 * dxx + 2.0 * w * sxy);
  s[1] = syy + dt * (lam * tr + mu2 * dyy - 2.0 * w * sxy);
  s[2] = sxy + dt * (mu2 * dxy + w * (syy - sxx));
  if (m.planeStrain) s[3] += dt * m.lambda * tr;
}

void neoHookeanStress(const Material &m, const double F[4], double s[4]) {
  const double J = F[0] * F[3] - F[1] * F[2];
  const double lnJ = std::log(J);
  const double bxx = F[0] * F[0] + F[1] * F[1];
  const double byy = F[2] * F[2] + F[3] * F[3];
  const double bxy = F[0] * F[2] + F[1] * F[3];
  s[0] = (m.lambda * lnJ + m.mu * (bxx - 1.0)) / J;
  s[1] = (m.lambda * lnJ + m.mu * (byy - 1.0)) / J;
  s[2] = m.mu * bxy / J;
  s[3] = m.lambda * lnJ / J;
}

double strainEnergy(const Material &m, const double s[4], const double F[4], double V0, double V) {
  if (m.model == MaterialModel::NeoHookean) {
    const double J = F[0] * F[3] - F[1] * F[2];
    const double lnJ = std::log(J);
    const double I1 = F[0] * F[0] + F[1] * F[1] + F[2] * F[2] + F[3] * F[3] + 1.0;
    return V0 * (0.5 * m.mu * (I1 - 3.0) - m.mu * lnJ + 0.5 * m.lambda * lnJ * lnJ);
  }
  const double sxx = s[0], syy = s[1], sxy = s[2], szz = s[3];
  const double w =
      ((sxx * sxx + syy * syy + szz * szz) - 2.0 * m.nu * (sxx * syy + syy * szz + szz * sxx)) /
          (2.0 * m.E) +
      (1.0 + m.nu) / m.E * sxy * sxy;
  return w * V;
}

} // namespace gimp::material
