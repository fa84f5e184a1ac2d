// Moments of a rectangle cut by circular holes (see include/gimp/geometry/cut_cell.hpp).
#include "gimp/geometry/cut_cell.hpp"

#include <algorithm>
#include <cmath>

namespace gimp::cut {

namespace {

// 16-point Gauss-Legendre nodes and weights on [-1, 1] (the positive half).
constexpr double kX[8] = {0.09501250983763745, 0.2816035507792589, 0.45801677765722737,
                          0.6178762444026438,  0.755404408355003,  0.8656312023878318,
                          0.9445750230732326,  0.9894009349916499};
constexpr double kW[8] = {0.18945061045506859,  0.1826034150449236,  0.16915651939500262,
                          0.14959598881657676,  0.12462897125553403, 0.09515851168249259,
                          0.062253523938647706, 0.027152459411754037};

/// Adds the moments of the strip x in [ox + r sin(t0), ox + r sin(t1)] between
/// max(y0, oy - r cos t) and min(y1, oy + r cos t) (where that is not empty).
void addPiece(double t0, double t1, double y0, double y1, double ox, double oy, double r,
              std::array<double, 5> &mom) {
  const double mid = 0.5 * (t0 + t1), half = 0.5 * (t1 - t0);
  for (int q = 0; q < 16; ++q) {
    const double t = mid + (q < 8 ? -kX[q] : kX[q - 8]) * half;
    const double w = kW[q % 8] * half;
    const double c = std::cos(t), x = ox + r * std::sin(t), dx = r * c * w;
    const double lo = std::max(y0, oy - r * c), hi = std::min(y1, oy + r * c);
    if (hi <= lo) continue;
    const double len = hi - lo;
    mom[0] += len * dx;
    mom[1] += x * len * dx;
    mom[2] += 0.5 * (hi * hi - lo * lo) * dx;
    mom[3] += x * x * len * dx;
    mom[4] += (hi * hi * hi - lo * lo * lo) / 3.0 * dx;
  }
}

} // namespace

std::array<double, 5> rectDiskMoments(double x0, double y0, double x1, double y1, double ox,
                                      double oy, double r) {
  std::array<double, 5> mom{};
  const double a = std::max(x0, ox - r), b = std::min(x1, ox + r);
  if (b <= a || y1 <= oy - r || y0 >= oy + r) return mom;
  auto angle = [&](double x) { return std::asin(std::clamp((x - ox) / r, -1.0, 1.0)); };
  std::vector<double> cuts = {angle(a), angle(b)};
  // Where the circle's top or bottom crosses y0 or y1: r cos t = |y - oy|.
  for (double y : {y0, y1}) {
    const double dy = std::fabs(y - oy);
    if (dy >= r) continue;
    const double t = std::acos(dy / r);
    for (double s : {-t, t})
      if (s > cuts[0] && s < cuts[1]) cuts.push_back(s);
  }
  std::sort(cuts.begin(), cuts.end());
  // Pieces of at most 0.5 rad: the integrands are trigonometric polynomials of degree 4 at
  // most, which 16 Gauss points integrate to round-off over such a piece.
  for (size_t i = 0; i + 1 < cuts.size(); ++i) {
    const int parts = static_cast<int>(std::ceil((cuts[i + 1] - cuts[i]) / 0.5));
    for (int k = 0; k < parts; ++k)
      addPiece(cuts[i] + k * (cuts[i + 1] - cuts[i]) / parts,
               cuts[i] + (k + 1) * (cuts[i + 1] - cuts[i]) / parts, y0, y1, ox, oy, r, mom);
  }
  return mom;
}

Moments rectMinusDisks(double x0, double y0, double x1, double y1,
                       const std::vector<std::array<double, 3>> &disks) {
  // In coordinates centred on the rectangle: the central second moments of a particle far from
  // the origin would otherwise be the small difference of two large numbers.
  const double w = x1 - x0, h = y1 - y0, xc = 0.5 * (x0 + x1), yc = 0.5 * (y0 + y1);
  std::array<double, 5> mom = centredRectangleMoments(w, h);
  for (const auto &d : disks) {
    const auto cut =
        rectDiskMoments(-0.5 * w, -0.5 * h, 0.5 * w, 0.5 * h, d[0] - xc, d[1] - yc, d[2]);
    for (int i = 0; i < 5; ++i)
      mom[i] -= cut[i];
  }
  return fromRaw(mom, xc, yc, w * h);
}

Moments fromRaw(const std::array<double, 5> &mom, double xc, double yc, double whole) {
  Moments m;
  // Round-off of a fully removed rectangle leaves about 1e-16 of its area.
  if (mom[0] <= 1e-13 * whole) return m;
  m.A = mom[0];
  const double dx = mom[1] / m.A, dy = mom[2] / m.A;
  m.cx = xc + dx;
  m.cy = yc + dy;
  m.Ixx = std::max(0.0, mom[3] - m.A * dx * dx);
  m.Iyy = std::max(0.0, mom[4] - m.A * dy * dy);
  return m;
}

void equivalentRectangle(const Moments &m, double l[2]) {
  // A rectangle of half-sizes a, b: area 4ab, Ixx = 4ab a^2 / 3.
  const double a = std::sqrt(3.0 * m.Ixx / m.A), b = std::sqrt(3.0 * m.Iyy / m.A);
  if (!(a > 0) || !(b > 0)) { // a degenerate sliver: the square of its area
    l[0] = l[1] = 0.5 * std::sqrt(m.A);
    return;
  }
  const double s = std::sqrt(m.A / (4.0 * a * b));
  l[0] = s * a;
  l[1] = s * b;
}

} // namespace gimp::cut
