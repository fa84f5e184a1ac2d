#include "gimp/grid/lattice.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace gimp {

namespace {

template <size_t N> std::string boxText(const std::array<double, N> &b) {
  std::string s;
  for (size_t d = 0; d < N; ++d)
    s += (d ? "," : "") + formatNumber(b[d]);
  return s;
}

/// Whether c / d is an integer (relative tolerance 1e-9); if so, m is set to it.
bool wholeMultiple(double c, double d, std::int64_t &m) {
  const double q = c / d;
  const double r = std::round(q);
  if (std::fabs(q - r) > 1e-9 * std::max(1.0, std::fabs(q))) return false;
  m = static_cast<std::int64_t>(r);
  return true;
}

const char *const kAxisName[3] = {"x", "y", "z"};

} // namespace

template <int D> void Lattice<D>::setLevels(double h0, const std::vector<LevelBox<D>> &boxes) {
  const size_t K = boxes.size();
  for (int a = 0; a < D; ++a)
    origin[a] = boxes[0].box[a];
  // Finest-lattice unit: h0 / (r1 r2 ...). Every node lies on this lattice.
  std::int64_t total = 1;
  for (size_t k = 1; k < K; ++k)
    total *= boxes[k].ratio;
  unit = h0 / static_cast<double>(total);
  levels.assign(K, Level<D>{});
  std::int64_t step = total;
  double h = h0;
  for (size_t k = 0; k < K; ++k) {
    Level<D> &L = levels[k];
    if (k > 0) {
      step /= boxes[k].ratio;
      h /= boxes[k].ratio;
    }
    L.h = h;
    L.ih = 1.0 / h;
    L.step = step;
    L.box = boxes[k].box;
    const std::string opt = "option -gimp_level" + std::to_string(k) + "_box " + boxText(L.box);
    std::int64_t c[2 * D];
    for (int d = 0; d < 2 * D; ++d) {
      const double o = origin[d % D];
      // Corners on the parent's grid lines (level 0: whole cells of h0 from the origin).
      const double parentH = k == 0 ? h0 : levels[k - 1].h;
      std::int64_t m = 0;
      if (!wholeMultiple(L.box[d] - o, parentH, m))
        throw InputError(opt + ": corner coordinate " + formatNumber(L.box[d]) +
                         " is not on a grid line of level " + std::to_string(k ? k - 1 : 0) +
                         " (lines at " + formatNumber(o) + " + i * " + formatNumber(parentH) + ")");
      c[d] = m * (k == 0 ? total : levels[k - 1].step);
    }
    // The box as the lattice has it: a corner accepted within the 1e-9 tolerance above would
    // otherwise put the level's cells (and the weights computed from its corner) off its nodes.
    for (int d = 0; d < 2 * D; ++d)
      L.box[d] = origin[d % D] + static_cast<double>(c[d]) * unit;
    bool empty = false, outside = false;
    for (int a = 0; a < D; ++a) {
      L.lo[a] = c[a];
      L.hi[a] = c[D + a];
      empty = empty || L.hi[a] <= L.lo[a];
      if (k > 0) {
        const Level<D> &P = levels[k - 1];
        outside = outside || L.lo[a] < P.lo[a] || L.hi[a] > P.hi[a];
      }
    }
    if (empty)
      throw InputError(
          opt + (D == 2 ? ": needs x1 > x0 and y1 > y0" : ": needs x1 > x0, y1 > y0 and z1 > z0"));
    if (outside)
      throw InputError(opt + ": not inside level " + std::to_string(k - 1) + "'s box " +
                       boxText(levels[k - 1].box) + " (levels must be nested)");
    for (int a = 0; a < D; ++a)
      L.n[a] = static_cast<PetscInt>((L.hi[a] - L.lo[a]) / L.step) + 1;
  }
}

template <int D> int Lattice<D>::leafLevelAtDoubled(const Index &a) const {
  const Level<D> &L0 = levels.front();
  for (int d = 0; d < D; ++d)
    if (a[d] < 2 * L0.lo[d] || a[d] > 2 * L0.hi[d]) return -1;
  for (int k = static_cast<int>(levels.size()) - 1; k > 0; --k) {
    const Level<D> &L = levels[k];
    bool in = true;
    for (int d = 0; d < D; ++d)
      in = in && a[d] > 2 * L.lo[d] && a[d] < 2 * L.hi[d];
    if (in) return k;
  }
  return 0;
}

template <int D> int Lattice<D>::leafLevelAt(const double *x) const {
  for (int k = static_cast<int>(levels.size()) - 1; k > 0; --k) {
    const BoxOf<D> &b = levels[k].box;
    bool in = true;
    for (int d = 0; d < D; ++d)
      in = in && x[d] > b[d] && x[d] < b[D + d];
    if (in) return k;
  }
  return 0;
}

template <int D> bool Lattice<D>::nodeActive(int k, const Index &i) const {
  const Level<D> &L = levels[k];
  // The node belongs to the finest level whose closed box contains it.
  for (int q = static_cast<int>(levels.size()) - 1; q > k; --q) {
    const Level<D> &F = levels[q];
    bool in = true;
    for (int d = 0; d < D; ++d) {
      const std::int64_t u = L.at(d, i[d]);
      in = in && u >= F.lo[d] && u <= F.hi[d];
    }
    if (in) return false;
  }
  return true;
}

template <int D> void Lattice<D>::zonesOf(int k, const Index &i, double z[2 * D]) const {
  const Level<D> &L = levels[k];
  Index a;
  for (int d = 0; d < D; ++d)
    a[d] = 2 * L.at(d, i[d]);
  // On each side of each axis, the smallest width of the 2^(D-1) leaf cells touching the node
  // there (centres at a + (+-1, ..., +-1) in doubled units, the side's axis fixed); 0 when the
  // side lies outside the domain.
  for (int ax = 0; ax < D; ++ax)
    for (int s = 0; s < 2; ++s) {
      double w = std::numeric_limits<double>::infinity();
      for (int c = 0; c < (1 << (D - 1)); ++c) {
        Index p = a;
        for (int d = 0, bit = 0; d < D; ++d)
          p[d] += d == ax ? (s ? 1 : -1) : ((c >> bit++) & 1 ? 1 : -1);
        const int q = leafLevelAtDoubled(p);
        w = std::min(w, q < 0 ? std::numeric_limits<double>::infinity() : levels[q].h);
      }
      z[2 * ax + s] = std::isinf(w) ? 0.0 : w;
    }
}

template <int D> std::int64_t Lattice<D>::activeNodes(int k) const {
  std::int64_t n = 0;
  forEachIndex<D>(levels[k].n, [&](const Index &i) { n += nodeActive(k, i); });
  return n;
}

template <int D> PetscInt Lattice<D>::lineIndex(int axis, double c) const {
  const Level<D> &L = levels[0];
  std::int64_t i = 0;
  if (!wholeMultiple(c - origin[axis], L.h, i) || i < 0 || i >= L.n[axis]) return -1;
  return static_cast<PetscInt>(i);
}

template <int D> std::string Lattice<D>::activeNodesCsv() const {
  std::string out = "level";
  for (int a = 0; a < D; ++a)
    out += std::string(",") + kAxisName[a];
  for (int a = 0; a < D; ++a)
    out += std::string(",L") + kAxisName[a] + "m,L" + kAxisName[a] + "p";
  out += "\n";
  char num[32];
  for (int k = 0; k < static_cast<int>(levels.size()); ++k)
    forEachIndex<D>(levels[k].n, [&](const Index &i) {
      if (!nodeActive(k, i)) return;
      double z[2 * D];
      zonesOf(k, i, z);
      out += std::to_string(k);
      for (int a = 0; a < D; ++a) {
        std::snprintf(num, sizeof(num), ",%.17g", nodeCoordinate(k, a, i[a]));
        out += num;
      }
      for (int s = 0; s < 2 * D; ++s) {
        std::snprintf(num, sizeof(num), ",%.17g", z[s]);
        out += num;
      }
      out += "\n";
    });
  return out;
}

template class Lattice<2>;
template class Lattice<3>;

} // namespace gimp
