// Unit tests of the constitutive updates in include/gimp/physics/material.hpp.
//
//   1. Jaumann (hypoelastic) update: a stressed particle in a pure rigid rotation keeps its
//      stress rotating with the body, with the first-order error of the explicit update that
//      the test derives below; a pure stretch rate adds (lambda* tr D I + 2 mu D) dt per step,
//      with szz = lambda tr D dt in plane strain and 0 in plane stress.
//   2. Neo-Hookean Cauchy stress against its closed form for uniaxial stretch, simple shear and a
//      rotated stretch, frame indifference (F -> R F gives R sigma R^T), zero stress at F = I.
//   3. strainEnergy: the linear complementary energy equals sigma : eps V / 2 for states whose
//      strain the test computes independently; the neo-Hookean energy's derivative is the first
//      Piola-Kirchhoff stress J sigma F^-T (times V0), by central differences.
//
// Material constants are derived here from E and nu with textbook formulas (plane-stress
// lambda* = E nu / (1 - nu^2), not the code's 2 mu lambda / (lambda + 2 mu)), so a wrong
// derivation in the code would show too. Random samples use a fixed-seed std::mt19937_64.
#include "gimp/physics/material.hpp"

#include "test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <random>

namespace {

using gimp::Material;
using gimp::MaterialModel;
using gimp::test::at;
using gimp::test::Worst;
using Tensor2 = gimp::Tensor<2>;

constexpr double kPi = 3.14159265358979323846;

Material material(MaterialModel model, bool planeStrain, double E = 2.0e7, double nu = 0.3) {
  Material m;
  m.model = model;
  m.E = E;
  m.nu = nu;
  m.rho = 1000.0;
  m.planeStrain = planeStrain;
  m.mu = E / (2.0 * (1.0 + nu));
  m.lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  m.lambdaStar = planeStrain ? m.lambda : E * nu / (1.0 - nu * nu);
  return m;
}

Tensor2 rotation(double theta) {
  Tensor2 R;
  R << std::cos(theta), -std::sin(theta), std::sin(theta), std::cos(theta);
  return R;
}

Tensor2 tensor(double xx, double xy, double yx, double yy) {
  Tensor2 t;
  t << xx, xy, yx, yy;
  return t;
}

/// Largest absolute entry.
double maxAbs(const Tensor2 &t) {
  return t.cwiseAbs().maxCoeff();
}

// ---------------------------------------------------------------------------------------------
// 1. Jaumann update.

struct SpinResult {
  double errExact;    // max entry |s_N - R s0 R^T|
  double errDiscrete; // max entry |s_N - (exact solution of the explicit recursion)|
  double bound;       // the recursion's predicted deviation from R s0 R^T
  double trace, det;  // |tr s_N - tr s0|, |det s_N - predicted det|
  double detDrift;    // |det s_N - det s0|
  double szz;         // |szz_N - szz0|
};

/// N explicit steps of a rigid rotation at rate omega through the total angle theta.
///
/// With W = omega [[0, -1], [1, 0]] the Jaumann rate of a rigid rotation is
/// ds/dt = W s - s W, solved by s(t) = R(omega t) s0 R^T. Write s = p I + dev with
/// z = (sxx - syy) / 2 + i sxy: p is unchanged and dz/dt = 2 i omega z. The explicit update is
/// z_{n+1} = (1 + 2 i omega dt) z_n, so z_N = (1 + 2 i omega dt)^N z0 against z0 e^{2 i theta}:
/// its modulus grows by (1 + 4 omega^2 dt^2)^{N/2} = 1 + 2 theta omega dt + ..., an error of
/// first order in dt (the phase error is third order per step), and det s = p^2 - |z|^2 drifts
/// by the same factor. Trace and szz (tr D = 0) do not change.
SpinResult spin(const Material &m, const Tensor2 &s0, double szz0, double omega, double theta,
                int N) {
  const double dt = theta / (omega * N);
  const Tensor2 L = tensor(0.0, -omega, omega, 0.0);
  Tensor2 s = s0;
  double szz = szz0;
  for (int n = 0; n < N; ++n)
    gimp::material::jaumannUpdate(m, L, dt, s, szz);

  const Tensor2 R = rotation(theta);
  const Tensor2 exact = R * s0 * R.transpose();
  const double p = 0.5 * s0.trace();
  const std::complex<double> z0(0.5 * (s0(0, 0) - s0(1, 1)), s0(0, 1));
  const std::complex<double> zN = std::pow(std::complex<double>(1.0, 2.0 * omega * dt), N) * z0;
  const Tensor2 discrete = tensor(p + zN.real(), zN.imag(), zN.imag(), p - zN.real());

  SpinResult r;
  r.errExact = maxAbs(s - exact);
  r.errDiscrete = maxAbs(s - discrete);
  // Each entry of s - R s0 R^T is a component of z_N - z0 e^{2 i theta}.
  r.bound = std::abs(zN - z0 * std::exp(std::complex<double>(0.0, 2.0 * theta)));
  r.trace = std::abs(s.trace() - s0.trace());
  r.det = std::abs(gimp::determinant2(s) - (p * p - std::norm(zN)));
  r.detDrift = std::abs(gimp::determinant2(s) - gimp::determinant2(s0));
  r.szz = std::abs(szz - szz0);
  return r;
}

TEST(Jaumann, RigidRotationRotatesTheStress) {
  const Tensor2 s0 = tensor(3.0e5, 1.5e5, 1.5e5, -2.0e5);
  const double szz0 = 0.4e5, omega = 2.0, theta = 1.2; // about 69 degrees
  const double scale = maxAbs(s0);
  for (bool planeStrain : {true, false}) {
    const Material m = material(MaterialModel::Linear, planeStrain);
    const SpinResult a = spin(m, s0, szz0, omega, theta, 1000);
    const SpinResult b = spin(m, s0, szz0, omega, theta, 2000);
    std::printf("  plane %s: |s - R s0 R^T| / |s0| = %.3e (N=1000), %.3e (N=2000), predicted "
                "%.3e, %.3e; vs recursion %.2e; trace %.2e, det vs predicted %.2e (drift from "
                "det0 %.3e), szz %.1e\n",
                planeStrain ? "strain" : "stress", a.errExact / scale, b.errExact / scale,
                a.bound / scale, b.bound / scale, a.errDiscrete / scale, a.trace / scale,
                a.det / (scale * scale), a.detDrift / (scale * scale), a.szz);
    for (const SpinResult &r : {a, b}) {
      // Against the rotated stress: the predicted first-order error of the explicit update
      // (2 theta omega dt |dev s0| = 2.4e-3 |dev s0| for N = 1000) plus round-off.
      EXPECT_LE(r.errExact, r.bound + 1e-12 * scale);
      EXPECT_GT(r.bound, 1e-4 * scale); // the bound is the method's error, not zero
      // Against the exact solution of the recursion: round-off of N steps (measured 1e-14;
      // N = 2000 steps of a few ulp each, 2000 * 4 * 1.1e-16 ~ 1e-12).
      EXPECT_LE(r.errDiscrete, 1e-12 * scale);
      // Invariants: the spin term is trace-free, so the trace changes only by round-off;
      // det s = p^2 - |z|^2 follows the recursion's growth of |z| (and tends to det s0 as dt -> 0).
      EXPECT_LE(r.trace, 1e-12 * scale);
      EXPECT_LE(r.det, 1e-12 * scale * scale);
      EXPECT_LE(r.szz, 0.0); // tr D = 0: szz is not touched at all
    }
    // First order: halving dt halves the error (the ratio is 2 up to O(omega dt)).
    EXPECT_NEAR(a.errExact / b.errExact, 2.0, 0.01);
    EXPECT_NEAR(a.detDrift / b.detDrift, 2.0, 0.01);
  }
}

TEST(Jaumann, PureStretchRateAddsTheElasticIncrement) {
  const double dt = 1.0e-3;
  // Symmetric velocity gradients (no spin): axial, shear and mixed.
  const Tensor2 Ls[] = {tensor(0.3, 0.0, 0.0, -0.1), tensor(0.0, 0.25, 0.25, 0.0),
                        tensor(-0.7, 0.2, 0.2, 0.45)};
  const Tensor2 s0s[] = {Tensor2::Zero(), tensor(1.0e5, -3.0e4, -3.0e4, 2.0e4)};
  Worst worst;
  for (bool planeStrain : {true, false}) {
    const Material m = material(MaterialModel::Linear, planeStrain);
    for (const Tensor2 &L : Ls)
      for (const Tensor2 &s0 : s0s) {
        Tensor2 s = s0;
        const double szz0 = planeStrain ? 5.0e3 : 0.0;
        double szz = szz0;
        gimp::material::jaumannUpdate(m, L, dt, s, szz);
        const double trD = L(0, 0) + L(1, 1);
        const Tensor2 expected =
            s0 + dt * (m.lambdaStar * trD * Tensor2::Identity() + 2.0 * m.mu * L);
        const double expectedSzz = szz0 + (planeStrain ? m.lambda * trD * dt : 0.0);
        // One step: a few rounding errors of the largest term (4 ulp).
        const double tol = 4.0 * 2.2e-16 * (maxAbs(s0) + maxAbs(expected));
        const double err = std::max(maxAbs(s - expected), std::abs(szz - expectedSzz)) / tol;
        worst.update(err, [&] {
          return at({{"plane strain", planeStrain},
                     {"Lxx", L(0, 0)},
                     {"Lxy", L(0, 1)},
                     {"Lyy", L(1, 1)},
                     {"|s0|", maxAbs(s0)}});
        });
      }
  }
  // In units of the tolerance above.
  EXPECT_WORST_LE(worst, 1.0);
  // Plane stress, uniaxial stress: the lateral strain rate D_yy = -nu D_xx keeps syy = 0 and
  // sxx grows at E D_xx (sxx = E / (1 - nu^2) (D_xx + nu D_yy) dt).
  const Material ps = material(MaterialModel::Linear, false);
  Tensor2 s = Tensor2::Zero();
  double szz = 0.0;
  gimp::material::jaumannUpdate(ps, tensor(1.0, 0.0, 0.0, -ps.nu), dt, s, szz);
  EXPECT_NEAR(s(0, 0), ps.E * dt, 1e-12 * ps.E * dt);
  EXPECT_NEAR(s(1, 1), 0.0, 1e-12 * ps.E * dt);
  EXPECT_EQ(szz, 0.0);
}

// ---------------------------------------------------------------------------------------------
// 2. Neo-Hookean stress.

struct Stress {
  Tensor2 s;
  double szz;
};

Stress neoHookean(const Material &m, const Tensor2 &F) {
  Stress r{Tensor2::Zero(), 0.0};
  gimp::material::neoHookeanStress(m, F, r.s, r.szz);
  return r;
}

// Closed forms: sigma = (lambda ln J I + mu (F F^T - I)) / J written out by hand per case.
TEST(NeoHookean, ClosedForms) {
  const Material m = material(MaterialModel::NeoHookean, true);
  const double lam = m.lambda, mu = m.mu;
  Worst worst;
  for (double a : {0.6, 0.95, 1.0, 1.3, 2.0}) {
    // Uniaxial stretch F = diag(a, 1): J = a, b = diag(a^2, 1).
    const Stress u = neoHookean(m, tensor(a, 0, 0, 1));
    const Tensor2 eu =
        tensor((lam * std::log(a) + mu * (a * a - 1.0)) / a, 0, 0, lam * std::log(a) / a);
    const double scale = lam + mu;
    worst.update(maxAbs(u.s - eu) / scale, [&] { return at({{"uniaxial a", a}}); });
    worst.update(std::abs(u.szz - lam * std::log(a) / a) / scale, [&] {
      return at({{"uniaxial szz a", a}});
    });
    // Simple shear F = [[1, g], [0, 1]]: J = 1, b = [[1 + g^2, g], [g, 1]].
    const double g = a - 1.0;
    const Stress sh = neoHookean(m, tensor(1, g, 0, 1));
    worst.update(maxAbs(sh.s - tensor(mu * g * g, mu * g, mu * g, 0.0)) / scale, [&] {
      return at({{"shear g", g}});
    });
    worst.update(std::abs(sh.szz) / scale, [&] { return at({{"shear szz g", g}}); });
    // Rotated stretch F = R(t) diag(a, c): J = a c, principal stresses
    // s1 = (lam ln J + mu (a^2 - 1)) / J, s2 = (lam ln J + mu (c^2 - 1)) / J on the rotated axes.
    for (double t : {0.3, 1.1, -2.0}) {
      const double c = 1.7 - 0.5 * a, J = a * c, co = std::cos(t), si = std::sin(t);
      const double s1 = (lam * std::log(J) + mu * (a * a - 1.0)) / J;
      const double s2 = (lam * std::log(J) + mu * (c * c - 1.0)) / J;
      const Stress r = neoHookean(m, tensor(co * a, -si * c, si * a, co * c));
      const Tensor2 e = tensor(co * co * s1 + si * si * s2, co * si * (s1 - s2),
                               co * si * (s1 - s2), si * si * s1 + co * co * s2);
      worst.update(maxAbs(r.s - e) / scale, [&] { return at({{"rotated a", a}, {"t", t}}); });
      worst.update(std::abs(r.szz - lam * std::log(J) / J) / scale, [&] {
        return at({{"rotated szz a", a}, {"t", t}});
      });
    }
  }
  // Relative to lambda + mu: a handful of roundings in ln, products and one division.
  EXPECT_WORST_LE(worst, 1e-14);
  // Zero stress in the reference state, exactly.
  const Stress z = neoHookean(m, Tensor2::Identity());
  EXPECT_EQ(maxAbs(z.s), 0.0);
  EXPECT_EQ(z.szz, 0.0);
}

TEST(NeoHookean, FrameIndifference) {
  const Material m = material(MaterialModel::NeoHookean, true);
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> U(-0.5, 0.5), angle(-kPi, kPi);
  Worst worst;
  for (int n = 0; n < 200; ++n) {
    Tensor2 F = Tensor2::Identity() + tensor(U(rng), U(rng), U(rng), U(rng));
    if (gimp::determinant2(F) < 0.2) continue;
    const double t = angle(rng);
    const Tensor2 R = rotation(t);
    const Stress a = neoHookean(m, F), b = neoHookean(m, R * F);
    const double scale = m.lambda + m.mu;
    worst.update(maxAbs(b.s - R * a.s * R.transpose()) / scale, [&] {
      return at({{"sample", double(n)}, {"angle", t}});
    });
    worst.update(std::abs(b.szz - a.szz) / scale, [&] { return at({{"szz sample", double(n)}}); });
  }
  // Products of entries up to 1.5 times mu, rounding of a few ulp each, then rotated.
  EXPECT_WORST_LE(worst, 1e-14);
}

// ---------------------------------------------------------------------------------------------
// 3. Strain energy.

TEST(StrainEnergy, LinearComplementaryEnergyIsHalfStressTimesStrain) {
  const double V0 = 2.0, V = 3.0; // the linear energy is per current volume
  for (bool planeStrain : {true, false}) {
    const Material m = material(MaterialModel::Linear, planeStrain);
    const double E = m.E, nu = m.nu;
    const Tensor2 I = Tensor2::Identity();
    // Uniaxial stress sxx = S (szz = 0, which in plane strain is a state with ezz != 0, still a
    // valid stress state for the complementary energy): exx = S / E.
    {
      const double S = 1.5e5;
      const double w = gimp::material::strainEnergy(m, tensor(S, 0, 0, 0), 0.0, I, V0, V);
      EXPECT_NEAR(w, 0.5 * S * (S / E) * V, 1e-14 * w);
    }
    // Pure shear sxy = T: exy = T / (2 mu) = (1 + nu) T / E, sigma : eps = 2 T exy.
    {
      const double T = -7.0e4;
      const double w = gimp::material::strainEnergy(m, tensor(0, T, T, 0), 0.0, I, V0, V);
      EXPECT_NEAR(w, 0.5 * 2.0 * T * ((1.0 + nu) * T / E) * V, 1e-14 * w);
    }
    // Uniaxial strain exx = e (plane strain; ezz = 0): sxx = (lambda + 2 mu) e,
    // syy = szz = lambda e, from the Lame constants of E and nu.
    if (planeStrain) {
      const double e = 2.0e-3;
      const double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
      const double w = gimp::material::strainEnergy(m, tensor((lam + 2 * mu) * e, 0, 0, lam * e),
                                                    lam * e, I, V0, V);
      EXPECT_NEAR(w, 0.5 * (lam + 2 * mu) * e * e * V, 1e-14 * w);
    }
    // Biaxial plane stress sxx = S, syy = Q: exx = (S - nu Q) / E, eyy = (Q - nu S) / E.
    if (!planeStrain) {
      const double S = 1.0e5, Q = -4.0e4;
      const double w = gimp::material::strainEnergy(m, tensor(S, 0, 0, Q), 0.0, I, V0, V);
      EXPECT_NEAR(w, 0.5 * (S * (S - nu * Q) + Q * (Q - nu * S)) / E * V, 1e-14 * w);
    }
  }
}

/// Neo-Hookean energy W(F) of a particle of reference volume V0.
double energy(const Material &m, const Tensor2 &F, double V0) {
  return gimp::material::strainEnergy(m, Tensor2::Zero(), 0.0, F, V0, 0.0);
}

TEST(StrainEnergy, NeoHookeanDerivativeIsTheStress) {
  const Material m = material(MaterialModel::NeoHookean, true);
  const double V0 = 0.37;
  EXPECT_EQ(energy(m, Tensor2::Identity(), V0), 0.0);
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> U(-0.4, 0.4);
  Worst worst;
  for (int n = 0; n < 100; ++n) {
    const Tensor2 F = Tensor2::Identity() + tensor(U(rng), U(rng), U(rng), U(rng));
    if (gimp::determinant2(F) < 0.3) continue;
    const Tensor2 dF = tensor(U(rng), U(rng), U(rng), U(rng));
    // First Piola-Kirchhoff stress P = J sigma F^-T; dW = V0 P : dF.
    const Stress c = neoHookean(m, F);
    // J F^-T = cofactor matrix of F: [[F_yy, -F_yx], [-F_xy, F_xx]].
    const Tensor2 P = c.s * tensor(F(1, 1), -F(1, 0), -F(0, 1), F(0, 0));
    const double exact = V0 * (P.cwiseProduct(dF)).sum();
    const double eps = 1.0e-5;
    const double fd = (energy(m, F + eps * dF, V0) - energy(m, F - eps * dF, V0)) / (2.0 * eps);
    // Central difference: truncation eps^2 W''' / 6 ~ 1e-10 and round-off
    // 1e-16 W / eps ~ 1e-11, relative to the scale V0 (lambda + mu) |dF|.
    const double scale = V0 * (m.lambda + m.mu) * maxAbs(dF);
    worst.update(std::abs(fd - exact) / scale, [&] { return at({{"sample", double(n)}}); });
  }
  EXPECT_WORST_LE(worst, 1e-8);
}

} // namespace
