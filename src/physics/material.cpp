#include "gimp/physics/material.hpp"

#include <cmath>

namespace gimp::material {

void neoHookeanStress(const Material &m, const Tensor<2> &F, Eigen::Ref<Tensor<2>> s, double &szz) {
  const double J = determinant<2>(F);
  const double lnJ = std::log(J);
  const Tensor<2> b = product<2>(F, F.transpose());
  s = ((m.lambda * lnJ) * Tensor<2>::Identity() + m.mu * (b - Tensor<2>::Identity())) / J;
  szz = m.lambda * lnJ / J;
}

double strainEnergy(const Material &m, const Tensor<2> &s, double szz, const Tensor<2> &F,
                    double V0, double V) {
  if (m.model == MaterialModel::NeoHookean) {
    const double J = determinant<2>(F);
    const double lnJ = std::log(J);
    const double I1 =
        F(0, 0) * F(0, 0) + F(0, 1) * F(0, 1) + F(1, 0) * F(1, 0) + F(1, 1) * F(1, 1) + 1.0;
    return V0 * (0.5 * m.mu * (I1 - 3.0) - m.mu * lnJ + 0.5 * m.lambda * lnJ * lnJ);
  }
  const double sxx = s(0, 0), syy = s(1, 1), sxy = s(0, 1);
  const double w =
      ((sxx * sxx + syy * syy + szz * szz) - 2.0 * m.nu * (sxx * syy + syy * szz + szz * sxx)) /
          (2.0 * m.E) +
      (1.0 + m.nu) / m.E * sxy * sxy;
  return w * V;
}

void jaumannUpdate(const Material &m, const Tensor<3> &L, double dt, Eigen::Ref<Tensor<3>> s) {
  // For a symmetric sigma and W = [[0, a, b], [-a, 0, c], [-b, -c, 0]] (the skew part of L),
  // W sigma - sigma W = M + M^T with M = W sigma: its six entries in closed form.
  const double a = 0.5 * (L(0, 1) - L(1, 0)), b = 0.5 * (L(0, 2) - L(2, 0)),
               c = 0.5 * (L(1, 2) - L(2, 1));
  const double s00 = s(0, 0), s11 = s(1, 1), s22 = s(2, 2), s01 = s(0, 1), s02 = s(0, 2),
               s12 = s(1, 2);
  const double lt = m.lambda * (L(0, 0) + L(1, 1) + L(2, 2)), mu2 = 2.0 * m.mu;
  const double n00 = lt + mu2 * L(0, 0) + 2.0 * (a * s01 + b * s02);
  const double n11 = lt + mu2 * L(1, 1) + 2.0 * (c * s12 - a * s01);
  const double n22 = lt + mu2 * L(2, 2) - 2.0 * (b * s02 + c * s12);
  const double n01 = m.mu * (L(0, 1) + L(1, 0)) + a * (s11 - s00) + b * s12 + c * s02;
  const double n02 = m.mu * (L(0, 2) + L(2, 0)) + b * (s22 - s00) + a * s12 - c * s01;
  const double n12 = m.mu * (L(1, 2) + L(2, 1)) + c * (s22 - s11) - a * s02 - b * s01;
  s(0, 0) = s00 + dt * n00;
  s(1, 1) = s11 + dt * n11;
  s(2, 2) = s22 + dt * n22;
  s(0, 1) = s(1, 0) = s01 + dt * n01;
  s(0, 2) = s(2, 0) = s02 + dt * n02;
  s(1, 2) = s(2, 1) = s12 + dt * n12;
}

void neoHookeanStress(const Material &m, const Tensor<3> &F, Eigen::Ref<Tensor<3>> s) {
  const double J = determinant<3>(F);
  const double lnJ = std::log(J);
  const Tensor<3> b = product<3>(F, F.transpose());
  s = ((m.lambda * lnJ) * Tensor<3>::Identity() + m.mu * (b - Tensor<3>::Identity())) / J;
}

double strainEnergy(const Material &m, const Tensor<3> &s, const Tensor<3> &F, double V0,
                    double V) {
  if (m.model == MaterialModel::NeoHookean) {
    const double J = determinant<3>(F);
    const double lnJ = std::log(J);
    const double I1 = F.squaredNorm();
    return V0 * (0.5 * m.mu * (I1 - 3.0) - m.mu * lnJ + 0.5 * m.lambda * lnJ * lnJ);
  }
  const double tr = s.trace();
  return ((1.0 + m.nu) * s.squaredNorm() - m.nu * tr * tr) / (2.0 * m.E) * V;
}

} // namespace gimp::material
