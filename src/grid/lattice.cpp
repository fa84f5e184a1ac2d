#include "gimp/grid/lattice.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace gimp {

namespace {

std::string boxText(const Box &b) {
  return formatNumber(b[0]) + "," + formatNumber(b[1]) + "," + formatNumber(b[2]) + "," +
         formatNumber(b[3]);
}

/// Whether c / d is an integer (relative tolerance 1e-9); if so, m is set to it.
bool wholeMultiple(double c, double d, std::int64_t &m) {
  const double q = c / d;
  const double r = std::round(q);
  if (std::fabs(q - r) > 1e-9 * std::max(1.0, std::fabs(q))) return false;
  m = static_cast<std::int64_t>(r);
  return true;
}

} // namespace

void Lattice::setGeometry(const Scene &sc) {
  const size_t K = sc.levels.size();
  x0 = sc.domain[0];
  y0 = sc.domain[1];
  // Finest-lattice unit: h0 / (r1 r2 ...). Every node lies on this lattice.
  std::int64_t total = 1;
  for (size_t k = 1; k < K; ++k)
    total *= sc.levels[k].ratio;
  unit = sc.h / static_cast<double>(total);
  levels.assign(K, Level{});
  std::int64_t step = total;
  double h = sc.h;
  for (size_t k = 0; k < K; ++k) {
    Level &L = levels[k];
    if (k > 0) {
      step /= sc.levels[k].ratio;
      h /= sc.levels[k].ratio;
    }
    L.h = h;
    L.ih = 1.0 / h;
    L.step = step;
    L.box = k == 0 ? sc.domain : sc.levels[k].box;
    const std::string opt = "option -gimp_level" + std::to_string(k) + "_box " + boxText(L.box);
    std::int64_t c[4];
    for (int d = 0; d < 4; ++d) {
      const double o = d % 2 == 0 ? x0 : y0;
      // Corners on the parent's grid lines (level 0: whole cells of h0 from the origin).
      const double parentH = k == 0 ? sc.h : levels[k - 1].h;
      std::int64_t m = 0;
      if (!wholeMultiple(L.box[d] - o, parentH, m))
        throw InputError(opt + ": corner coordinate " + formatNumber(L.box[d]) +
                         " is not on a grid line of level " + std::to_string(k ? k - 1 : 0) +
                         " (lines at " + formatNumber(o) + " + i * " + formatNumber(parentH) + ")");
      c[d] = m * (k == 0 ? total : levels[k - 1].step);
    }
    // The box as the lattice has it: a corner accepted within the 1e-9 tolerance above would
    // otherwise put the level's cells (and the weights computed from its corner) off its nodes.
    for (int d = 0; d < 4; ++d)
      L.box[d] = (d % 2 == 0 ? x0 : y0) + static_cast<double>(c[d]) * unit;
    L.u0 = c[0];
    L.v0 = c[1];
    L.u1 = c[2];
    L.v1 = c[3];
    if (L.u1 <= L.u0 || L.v1 <= L.v0) throw InputError(opt + ": needs x1 > x0 and y1 > y0");
    if (k > 0) {
      const Level &P = levels[k - 1];
      if (L.u0 < P.u0 || L.v0 < P.v0 || L.u1 > P.u1 || L.v1 > P.v1)
        throw InputError(opt + ": not inside level " + std::to_string(k - 1) + "'s box " +
                         boxText(P.box) + " (levels must be nested)");
    }
    L.M = static_cast<PetscInt>((L.u1 - L.u0) / L.step) + 1;
    L.N = static_cast<PetscInt>((L.v1 - L.v0) / L.step) + 1;
  }
}

int Lattice::leafLevelAt2(std::int64_t a, std::int64_t b) const {
  const Level &D = levels.front();
  if (a < 2 * D.u0 || a > 2 * D.u1 || b < 2 * D.v0 || b > 2 * D.v1) return -1;
  for (int k = static_cast<int>(levels.size()) - 1; k > 0; --k) {
    const Level &L = levels[k];
    if (a > 2 * L.u0 && a < 2 * L.u1 && b > 2 * L.v0 && b < 2 * L.v1) return k;
  }
  return 0;
}

int Lattice::leafLevelAt(double x, double y) const {
  for (int k = static_cast<int>(levels.size()) - 1; k > 0; --k) {
    const Box &b = levels[k].box;
    if (x > b[0] && x < b[2] && y > b[1] && y < b[3]) return k;
  }
  return 0;
}

bool Lattice::nodeActive(int k, std::int64_t i, std::int64_t j) const {
  const Level &L = levels[k];
  const std::int64_t u = L.u0 + i * L.step, v = L.v0 + j * L.step;
  // The node belongs to the finest level whose closed box contains it.
  for (int q = static_cast<int>(levels.size()) - 1; q > k; --q) {
    const Level &F = levels[q];
    if (u >= F.u0 && u <= F.u1 && v >= F.v0 && v <= F.v1) return false;
  }
  return true;
}

void Lattice::zonesOf(int k, std::int64_t i, std::int64_t j, double z[4]) const {
  const Level &L = levels[k];
  const std::int64_t a = 2 * (L.u0 + i * L.step), b = 2 * (L.v0 + j * L.step);
  // Width of the leaf cell containing the point (a + da, b + db), or +inf outside the domain.
  auto width = [&](int da, int db) {
    const int q = leafLevelAt2(a + da, b + db);
    return q < 0 ? std::numeric_limits<double>::infinity() : levels[q].h;
  };
  const double side[4][2] = {{width(-1, -1), width(-1, 1)}, // Lx-
                             {width(1, -1), width(1, 1)},   // Lx+
                             {width(-1, -1), width(1, -1)}, // Ly-
                             {width(-1, 1), width(1, 1)}};  // Ly+
  for (int s = 0; s < 4; ++s) {
    const double w = std::min(side[s][0], side[s][1]);
    z[s] = std::isinf(w) ? 0.0 : w;
  }
}

std::int64_t Lattice::activeNodes(int k) const {
  const Level &L = levels[k];
  std::int64_t n = 0;
  for (PetscInt j = 0; j < L.N; ++j)
    for (PetscInt i = 0; i < L.M; ++i)
      n += nodeActive(k, i, j);
  return n;
}

PetscInt Lattice::lineIndex(int axis, double c) const {
  const Level &L = levels[0];
  const double o = axis == 0 ? x0 : y0;
  const PetscInt n = axis == 0 ? L.M : L.N;
  std::int64_t i = 0;
  if (!wholeMultiple(c - o, L.h, i) || i < 0 || i >= n) return -1;
  return static_cast<PetscInt>(i);
}

std::string Lattice::activeNodesCsv() const {
  std::string out = "level,x,y,Lxm,Lxp,Lym,Lyp\n";
  char row[256];
  for (int k = 0; k < static_cast<int>(levels.size()); ++k) {
    const Level &L = levels[k];
    for (PetscInt j = 0; j < L.N; ++j)
      for (PetscInt i = 0; i < L.M; ++i) {
        if (!nodeActive(k, i, j)) continue;
        double z[4];
        zonesOf(k, i, j, z);
        std::snprintf(row, sizeof(row), "%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", k,
                      x0 + static_cast<double>(L.u0 + i * L.step) * unit,
                      y0 + static_cast<double>(L.v0 + j * L.step) * unit, z[0], z[1], z[2], z[3]);
        out += row;
      }
  }
  return out;
}

} // namespace gimp
