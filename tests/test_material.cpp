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
//   4. The 3D models: Jaumann's rigid rotation about an oblique axis (first order, trace kept) and
//      stretch rate (Hooke with lambda), neo-Hookean closed form, frame indifference and small
//      strain limit, energies as in 3, and the 2D plane-strain models equal to the 3D ones on
//      in-plane states.
//
// Material constants are derived here from E and nu with textbook formulas (plane-stress
// lambda* = E nu / (1 - nu^2), not the code's 2 mu lambda / (lambda + 2 mu)), so a wrong
// derivation in the code would show too. Random samples use a fixed-seed std::mt19937_64.
#include "gimp/physics/material.hpp"

#include "test_util.hpp"

#include <Eigen/LU>
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
  r.det = std::abs(gimp::determinant<2>(s) - (p * p - std::norm(zN)));
  r.detDrift = std::abs(gimp::determinant<2>(s) - gimp::determinant<2>(s0));
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
    if (gimp::determinant<2>(F) < 0.2) continue;
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
    if (gimp::determinant<2>(F) < 0.3) continue;
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

// ---------------------------------------------------------------------------------------------
// 4. The 3D models.

using Tensor3 = gimp::Tensor<3>;

// The 3D models take lambda itself: the materials below are built as plane stress, whose
// lambdaStar (E nu / (1 - nu^2)) differs from lambda, so a 3D update that read lambdaStar fails.

/// Rotation by angle t about the unit axis n (Rodrigues).
Tensor3 rotation3(const Eigen::Vector3d &n, double t) {
  Tensor3 K;
  K << 0, -n[2], n[1], n[2], 0, -n[0], -n[1], n[0], 0;
  return Tensor3::Identity() + std::sin(t) * K + (1 - std::cos(t)) * K * K;
}

Tensor3 randomTensor3(std::mt19937_64 &rng, double a) {
  std::uniform_real_distribution<double> U(-a, a);
  Tensor3 t;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      t(i, j) = U(rng);
  return t;
}

Tensor3 neoHookean3(const Material &m, const Tensor3 &F) {
  Tensor3 s = Tensor3::Zero();
  gimp::material::neoHookeanStress(m, F, s);
  return s;
}

TEST(Material3D, JaumannRigidRotationAboutAnObliqueAxis) {
  const Material m = material(MaterialModel::Linear, false);
  const Eigen::Vector3d n = Eigen::Vector3d(1.0, -2.0, 0.5).normalized();
  const double omega = 3.0, theta = 0.9;
  Tensor3 W;
  W << 0, -n[2], n[1], n[2], 0, -n[0], -n[1], n[0], 0;
  W *= omega;
  Tensor3 s0;
  s0 << 2.0e5, -3.0e4, 5.0e4, -3.0e4, -1.0e5, 2.0e4, 5.0e4, 2.0e4, 7.0e4;
  const Tensor3 exact = rotation3(n, theta) * s0 * rotation3(n, theta).transpose();
  double err[2];
  for (int q = 0; q < 2; ++q) {
    const int N = 2000 << q;
    const double dt = theta / (omega * N);
    Tensor3 s = s0;
    for (int k = 0; k < N; ++k)
      gimp::material::jaumannUpdate(m, W, dt, s);
    err[q] = (s - exact).cwiseAbs().maxCoeff() / s0.cwiseAbs().maxCoeff();
    // tr(W s - s W) = 0 and the stress stays symmetric in every step.
    EXPECT_NEAR(s.trace(), s0.trace(), 1e-9 * s0.cwiseAbs().maxCoeff());
    EXPECT_LE((s - s.transpose()).cwiseAbs().maxCoeff(), 1e-9 * s0.cwiseAbs().maxCoeff());
  }
  std::printf("  rigid rotation: error %.3g at N = 2000, %.3g at N = 4000 (ratio %.3f)\n", err[0],
              err[1], err[0] / err[1]);
  // The explicit update is first order: the error halves with dt, and is small.
  EXPECT_NEAR(err[0] / err[1], 2.0, 0.05);
  EXPECT_LT(err[1], 2e-3);
}

TEST(Material3D, JaumannStretchRateIsHooke) {
  const Material m = material(MaterialModel::Linear, false);
  // Lame constants from E and nu by the textbook formulas.
  const double lam = m.E * m.nu / ((1 + m.nu) * (1 - 2 * m.nu)), mu = m.E / (2 * (1 + m.nu));
  std::mt19937_64 rng(31);
  for (int k = 0; k < 20; ++k) {
    const Tensor3 A = randomTensor3(rng, 1.0);
    const Tensor3 D = 0.5 * (A + A.transpose());
    const double dt = 1e-4;
    Tensor3 s = Tensor3::Zero();
    gimp::material::jaumannUpdate(m, D, dt, s);
    const Tensor3 hooke = dt * (lam * D.trace() * Tensor3::Identity() + 2 * mu * D);
    EXPECT_LE((s - hooke).cwiseAbs().maxCoeff(), 1e-14 * hooke.cwiseAbs().maxCoeff());
  }
}

TEST(Material3D, NeoHookean) {
  const Material m = material(MaterialModel::NeoHookean, false);
  // Zero stress at F = I and under a rotation.
  EXPECT_EQ(neoHookean3(m, Tensor3::Identity()).cwiseAbs().maxCoeff(), 0.0);
  const Tensor3 R = rotation3(Eigen::Vector3d(0.3, 0.4, -0.2).normalized(), 1.1);
  EXPECT_LE(neoHookean3(m, R).cwiseAbs().maxCoeff(), 1e-8 * m.mu);
  // Uniaxial stretch F = diag(a, 1, 1): sxx = (lambda ln a + mu (a^2 - 1)) / a, syy = szz =
  // lambda ln a / a.
  for (double a : {0.7, 1.3}) {
    Tensor3 F = Tensor3::Identity();
    F(0, 0) = a;
    const Tensor3 s = neoHookean3(m, F);
    EXPECT_NEAR(s(0, 0), (m.lambda * std::log(a) + m.mu * (a * a - 1)) / a, 1e-9 * m.mu);
    EXPECT_NEAR(s(1, 1), m.lambda * std::log(a) / a, 1e-9 * m.mu);
    EXPECT_NEAR(s(2, 2), m.lambda * std::log(a) / a, 1e-9 * m.mu);
    EXPECT_EQ(s(0, 1), 0.0);
  }
  std::mt19937_64 rng(5);
  Worst frame, small, plane;
  for (int k = 0; k < 200; ++k) {
    const Tensor3 F = Tensor3::Identity() + randomTensor3(rng, 0.3);
    if (F.determinant() < 0.3) continue;
    // Frame indifference: sigma(R F) = R sigma(F) R^T.
    const Tensor3 Rk = rotation3(randomTensor3(rng, 1.0).col(0).normalized(), 2.0 * k);
    frame.update(
        (neoHookean3(m, Rk * F) - Rk * neoHookean3(m, F) * Rk.transpose()).cwiseAbs().maxCoeff() /
            (m.lambda + m.mu),
        [&] {
          return at({{"sample", double(k)}});
        });
    // Small strain: Hooke's law to first order.
    const Tensor3 G = randomTensor3(rng, 1e-6);
    const Tensor3 e = 0.5 * (G + G.transpose());
    const Tensor3 hooke = m.lambda * e.trace() * Tensor3::Identity() + 2 * m.mu * e;
    small.update((neoHookean3(m, Tensor3::Identity() + G) - hooke).cwiseAbs().maxCoeff() /
                     hooke.cwiseAbs().maxCoeff(),
                 [&] {
                   return at({{"sample", double(k)}});
                 });
    // The 2D plane-strain model is the 3D one with F_zz = 1 (szz included).
    Tensor3 F3 = Tensor3::Identity();
    F3.block<2, 2>(0, 0) = F.block<2, 2>(0, 0);
    if (F3.determinant() < 0.3) continue;
    const Stress s2 = neoHookean(material(MaterialModel::NeoHookean, true), F.block<2, 2>(0, 0));
    const Tensor3 s3 = neoHookean3(m, F3);
    plane.update(
        std::max((s2.s - s3.block<2, 2>(0, 0)).cwiseAbs().maxCoeff(), std::abs(s2.szz - s3(2, 2))) /
            (m.lambda + m.mu),
        [&] {
          return at({{"sample", double(k)}});
        });
  }
  EXPECT_WORST_LE(frame, 1e-14);
  EXPECT_WORST_LE(small, 1e-5);
  EXPECT_WORST_LE(plane, 1e-15);
}

TEST(Material3D, StrainEnergies) {
  const double V0 = 2.0, V = 3.0;
  {
    const Material m = material(MaterialModel::Linear, false);
    const Tensor3 I = Tensor3::Identity();
    const double E = m.E, nu = m.nu;
    const double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
    // Uniaxial stress: exx = S / E.
    Tensor3 s = Tensor3::Zero();
    s(0, 0) = 1.5e5;
    double w = gimp::material::strainEnergy(m, s, I, V0, V);
    EXPECT_NEAR(w, 0.5 * s(0, 0) * s(0, 0) / E * V, 1e-14 * w);
    // Shear syz = T: eps_yz = T / (2 mu); sigma : eps = 2 T eps_yz.
    s = Tensor3::Zero();
    s(1, 2) = s(2, 1) = -7.0e4;
    w = gimp::material::strainEnergy(m, s, I, V0, V);
    EXPECT_NEAR(w, 0.5 * 2 * s(1, 2) * s(1, 2) / (2 * mu) * V, 1e-14 * w);
    // Uniaxial strain e along z: sigma = diag(lam, lam, lam + 2 mu) e, w = (lam + 2 mu) e^2 / 2.
    const double e = 2e-3;
    s = lam * e * Tensor3::Identity();
    s(2, 2) += 2 * mu * e;
    w = gimp::material::strainEnergy(m, s, I, V0, V);
    EXPECT_NEAR(w, 0.5 * (lam + 2 * mu) * e * e * V, 1e-13 * w);
    // A plane-strain state has the 2D model's energy.
    Tensor2 s2;
    s2 << 1.0e5, 3.0e4, 3.0e4, -2.0e4;
    const double szz = 2.5e4;
    Tensor3 s3 = Tensor3::Zero();
    s3.block<2, 2>(0, 0) = s2;
    s3(2, 2) = szz;
    EXPECT_NEAR(gimp::material::strainEnergy(m, s3, I, V0, V),
                gimp::material::strainEnergy(m, s2, szz, Tensor2::Identity(), V0, V),
                1e-14 * gimp::material::strainEnergy(m, s2, szz, Tensor2::Identity(), V0, V));
  }
  {
    // Neo-Hookean: dW = V0 P : dF with P = J sigma F^-T, by central differences.
    const Material m = material(MaterialModel::NeoHookean, false);
    auto W = [&](const Tensor3 &F) {
      return gimp::material::strainEnergy(m, Tensor3::Zero(), F, V0, 0.0);
    };
    EXPECT_EQ(W(Tensor3::Identity()), 0.0);
    std::mt19937_64 rng(91);
    Worst worst;
    for (int k = 0; k < 100; ++k) {
      const Tensor3 F = Tensor3::Identity() + randomTensor3(rng, 0.3);
      if (F.determinant() < 0.3) continue;
      const Tensor3 dF = randomTensor3(rng, 0.4);
      const Tensor3 P = F.determinant() * neoHookean3(m, F) * F.inverse().transpose();
      const double exact = V0 * P.cwiseProduct(dF).sum();
      const double eps = 1e-5;
      const double fd = (W(F + eps * dF) - W(F - eps * dF)) / (2 * eps);
      worst.update(std::abs(fd - exact) / (V0 * (m.lambda + m.mu) * dF.cwiseAbs().maxCoeff()), [&] {
        return at({{"sample", double(k)}});
      });
    }
    EXPECT_WORST_LE(worst, 1e-8);
  }
}

TEST(Material3D, JaumannPlaneStrainMatches2D) {
  // An in-plane velocity gradient: the 3D update equals the 2D plane-strain one (szz = s_zz).
  const Material m = material(MaterialModel::Linear, false);
  const Material m2 = material(MaterialModel::Linear, true); // the 2D model in plane strain
  std::mt19937_64 rng(17);
  for (int k = 0; k < 50; ++k) {
    const Tensor3 A = randomTensor3(rng, 1.0);
    Tensor3 L = Tensor3::Zero();
    L.block<2, 2>(0, 0) = A.block<2, 2>(0, 0);
    Tensor3 s3 = Tensor3::Zero();
    s3.block<2, 2>(0, 0) = 1e5 * (A + A.transpose()).block<2, 2>(0, 0);
    s3(2, 2) = 3e4;
    Tensor2 s2 = s3.block<2, 2>(0, 0);
    double szz = s3(2, 2);
    gimp::material::jaumannUpdate(m2, Tensor2(L.block<2, 2>(0, 0)), 1e-3, s2, szz);
    gimp::material::jaumannUpdate(m, L, 1e-3, s3);
    EXPECT_LE((s2 - s3.block<2, 2>(0, 0)).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_NEAR(szz, s3(2, 2), 1e-9);
    EXPECT_EQ(s3(0, 2), 0.0);
  }
}

} // namespace
