#include "gimp/cracks/williams.hpp"

#include <cmath>

namespace gimp::cracks {

namespace {

constexpr double kTwoPi = 6.283185307179586;

/// The angular functions of the displacement, u = sqrt(r / 2 pi) / (2 mu) f(theta), and their
/// derivatives df/dtheta.
void angular(int mode, double th, double kappa, double f[2], double df[2]) {
  const double c = std::cos(0.5 * th), s = std::sin(0.5 * th), ct = std::cos(th), st = std::sin(th);
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

} // namespace

void williamsDisplacement(int mode, double r, double theta, const TipElastic &e, double u[2]) {
  double f[2], df[2];
  angular(mode, theta, e.kappa, f, df);
  const double a = std::sqrt(r / kTwoPi) / (2.0 * e.mu);
  u[0] = a * f[0];
  u[1] = a * f[1];
}

void williamsField(int mode, double r, double theta, const TipElastic &e, double s[3],
                   double du1[2]) {
  const double c = std::cos(0.5 * theta), sn = std::sin(0.5 * theta);
  const double c3 = std::cos(1.5 * theta), s3 = std::sin(1.5 * theta);
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
  // d/dx1 = cos(theta) d/dr - sin(theta) / r d/dtheta on u = sqrt(r / 2 pi) f / (2 mu).
  double f[2], df[2];
  angular(mode, theta, e.kappa, f, df);
  const double ct = std::cos(theta), st = std::sin(theta);
  for (int i = 0; i < 2; ++i)
    du1[i] = k / (2.0 * e.mu) * (0.5 * ct * f[i] - st * df[i]);
}

} // namespace gimp::cracks
