#include "gimp/physics/mms.hpp"

#include <cmath>

namespace gimp::mms {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

AxialWave::AxialWave(double amplitude, const Material &m)
    : A(amplitude), c(std::sqrt(m.E / m.rho)) {}

double AxialWave::u(double X, double t) const {
  return A * std::sin(2 * kPi * X) * std::cos(c * kPi * t);
}

double AxialWave::F(double X, double t) const {
  return 1.0 + 2 * kPi * A * std::cos(2 * kPi * X) * std::cos(c * kPi * t);
}

double AxialWave::bodyForce(double X, double t) const {
  const double f = F(X, t);
  return c * c * kPi * kPi * u(X, t) * (1.0 + 2.0 / (f * f));
}

} // namespace gimp::mms
