#include "gimp/cracks/williams.hpp"

#include <cmath>

namespace gimp::cracks {

namespace {

constexpr double kTwoPi = 6.283185307179586;

/// The trigonometric values of theta that the fields take: of theta / 2, theta and 3 theta / 2,
/// each found once (every field of a point, of every mode, shares them).
struct Trig {
  double c, s, ct, st, c3, s3;
  explicit Trig(double th)
      : c(std::cos(0.5 * th)), s(std::sin(0.5 * th)), ct(std::cos(th)), st(std::sin(th)),
        c3(std::cos(1.5 * th)), s3(std::sin(1.5 * th)) {}
};

/// The angular functions of the displacement, u = sqrt(r / 2 pi) / (2 mu) f(theta), and their
/// derivatives df/dtheta.
void angular(int mode, const Trig &t, double kappa, double f[2], double df[2]) {
  const double c = t.c, s = t.s, ct = t.ct, st = t.st;
  if (mode == 1) {
    f[0] = c * (kappa - ct);
    f[1] = s * (kappa - ct);
    df[0] = -0.5 * s * (kappa - ct) + c * st;
    df[1] = 0.5 * c * (kappa - ct) + s * st;
  } else {
    f[0] = s * (kappa + 2.0 + ct);
    f[1] = -c * (kappa - 2.0 + ct);
    df[0] = 0.5 * c * (kappa + 2.0 + ct) - s * st;
    df[1] = 0.5 * s * (kappa - 2.0 + ct) + c * st;
  }
}

/// The gradient (d/dx1, d/dx2) in the tip frame of a displacement component u = A sqrt(r) f(theta)
/// with df = df/dtheta: d/dx1 = cos(theta) d/dr - sin(theta) / r d/dtheta, d/dx2 = sin(theta) d/dr
/// + cos(theta) / r d/dtheta.
void polarGradient(double A, double r, const Trig &t, double f, double df, double g[2]) {
  const double ct = t.ct, st = t.st, k = A / std::sqrt(r);
  g[0] = k * (0.5 * ct * f - st * df);
  g[1] = k * (0.5 * st * f + ct * df);
}

/// The antiplane (mode III) displacement's angular function, u3 = sqrt(r / 2 pi) / (2 mu) f, and
/// df/dtheta: f = 4 sin(theta / 2), u3 = (2 / mu) sqrt(r / 2 pi) sin(theta / 2).
void angularAntiplane(const Trig &t, double &f, double &df) {
  f = 4.0 * t.s;
  df = 2.0 * t.c;
}

/// The in-plane Williams stress of mode 1 or 2 (s11, s22, s12) at (r, theta) for a unit K.
void williamsStress(int mode, double r, const Trig &t, double s[3]) {
  const double c = t.c, sn = t.s, c3 = t.c3, s3 = t.s3;
  const double k = 1.0 / std::sqrt(kTwoPi * r);
  if (mode == 1) {
    s[0] = k * c * (1.0 - sn * s3);
    s[1] = k * c * (1.0 + sn * s3);
    s[2] = k * sn * c * c3;
  } else {
    s[0] = -k * sn * (2.0 + c * c3);
    s[1] = k * sn * c * c3;
    s[2] = k * c * (1.0 - sn * s3);
  }
}

/// frontField with the point's trigonometric values.
void frontFieldAt(int mode, double r, const Trig &t, const TipElastic &e, double s[3][3],
                  double g[3][3]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      s[i][j] = g[i][j] = 0.0;
  const double A = 1.0 / (2.0 * e.mu * std::sqrt(kTwoPi));
  if (mode == 3) {
    // Antiplane shear: s13 = -sin(theta / 2) / sqrt(2 pi r), s23 = cos(theta / 2) / sqrt(2 pi r).
    const double k = 1.0 / std::sqrt(kTwoPi * r);
    s[0][2] = s[2][0] = -k * t.s;
    s[1][2] = s[2][1] = k * t.c;
    double f, df;
    angularAntiplane(t, f, df);
    polarGradient(A, r, t, f, df, g[2]);
    return;
  }
  // Plane strain: the in-plane Williams field, no strain along the front, s33 = nu (s11 + s22)
  // with nu = (3 - kappa) / 4.
  double sp[3], f[2], df[2];
  williamsStress(mode, r, t, sp);
  s[0][0] = sp[0];
  s[1][1] = sp[1];
  s[0][1] = s[1][0] = sp[2];
  s[2][2] = 0.25 * (3.0 - e.kappa) * (sp[0] + sp[1]);
  angular(mode, t, e.kappa, f, df);
  for (int i = 0; i < 2; ++i)
    polarGradient(A, r, t, f[i], df[i], g[i]);
}

} // namespace

void williamsDisplacement(int mode, double r, double theta, const TipElastic &e, double u[2]) {
  double f[2], df[2];
  angular(mode, Trig(theta), e.kappa, f, df);
  const double a = std::sqrt(r / kTwoPi) / (2.0 * e.mu);
  u[0] = a * f[0];
  u[1] = a * f[1];
}

void williamsField(int mode, double r, double theta, const TipElastic &e, double s[3],
                   double du1[2]) {
  const Trig t(theta);
  williamsStress(mode, r, t, s);
  // d/dx1 = cos(theta) d/dr - sin(theta) / r d/dtheta on u = sqrt(r / 2 pi) f / (2 mu), in the
  // order of operations the 2D tips have always used (polarGradient's would move their round-off).
  double f[2], df[2];
  angular(mode, t, e.kappa, f, df);
  const double k = 1.0 / std::sqrt(kTwoPi * r);
  const double ct = t.ct, st = t.st;
  for (int i = 0; i < 2; ++i)
    du1[i] = k / (2.0 * e.mu) * (0.5 * ct * f[i] - st * df[i]);
}

void frontDisplacement(int mode, double r, double theta, const TipElastic &e, double u[3]) {
  const double A = std::sqrt(r / kTwoPi) / (2.0 * e.mu);
  double f[2] = {0, 0}, df[2], f3 = 0, df3;
  const Trig t(theta);
  if (mode == 3)
    angularAntiplane(t, f3, df3);
  else
    angular(mode, t, e.kappa, f, df);
  u[0] = A * f[0];
  u[1] = A * f[1];
  u[2] = A * f3;
}

void frontField(int mode, double r, double theta, const TipElastic &e, double s[3][3],
                double g[3][3]) {
  frontFieldAt(mode, r, Trig(theta), e, s, g);
}

void frontFields(double r, double theta, const TipElastic &e, double s[3][3][3],
                 double g[3][3][3]) {
  const Trig t(theta);
  for (int m = 0; m < 3; ++m)
    frontFieldAt(m + 1, r, t, e, s[m], g[m]);
}

} // namespace gimp::cracks
