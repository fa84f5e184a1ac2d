// Shared helpers of the 3D composite-grid tests (test_grid3d.cpp, test_kernels3d.cpp): the 3D
// refined layouts they run on, lattices and level boxes built from them, and a random particle
// sampler.
#pragma once

#include "gimp/grid/lattice.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace gimp::test3d {

constexpr int D = 3;
using Lattice3 = Lattice<D>;
using Level3 = Level<D>;
using Box3 = BoxOf<D>;

// Domain origin and level-0 cell size that are not binary fractions, so node coordinates carry
// round-off as in real scenes.
constexpr double kX0 = -1.3, kY0 = 0.7, kZ0 = 2.1, kH0 = 0.37;

/// A refined box in level-0 cells from the origin (fractions where they fall on the parent's
/// lines) and its ratio.
struct BoxSpec {
  std::array<double, 6> c;
  int ratio;
};
struct Layout {
  std::string name;
  std::array<int, 3> cells; // level-0 cells of the domain per axis
  std::vector<BoxSpec> boxes;
};

inline std::vector<LevelBox<D>> boxesOf(const Layout &lay) {
  const double o[3] = {kX0, kY0, kZ0};
  std::vector<LevelBox<D>> b(1);
  for (int a = 0; a < D; ++a) {
    b[0].box[a] = o[a];
    b[0].box[D + a] = o[a] + lay.cells[a] * kH0;
  }
  for (const BoxSpec &s : lay.boxes) {
    LevelBox<D> L;
    for (int d = 0; d < 2 * D; ++d)
      L.box[d] = o[d % D] + s.c[d] * kH0;
    L.ratio = s.ratio;
    b.push_back(L);
  }
  return b;
}

inline Lattice3 latticeOf(const Layout &lay) {
  Lattice3 g;
  g.setLevels(kH0, boxesOf(lay));
  return g;
}

inline std::vector<Layout> twoLevelLayouts() {
  std::vector<Layout> v;
  for (int r : {2, 3, 4}) {
    const std::string s = " r=" + std::to_string(r);
    v.push_back({"middle" + s, {6, 5, 4}, {{{2, 1, 1, 4, 3, 3}, r}}});
    v.push_back({"domain face" + s, {6, 5, 4}, {{{0, 1, 1, 2, 4, 3}, r}}});
    v.push_back({"domain corner" + s, {6, 5, 4}, {{{4, 3, 2, 6, 5, 4}, r}}});
    v.push_back({"one cell" + s, {6, 5, 4}, {{{3, 2, 1, 4, 3, 2}, r}}});
  }
  return v;
}

/// 3-level layouts (level-2 box in level-1 cells f = 1 / r1): in the middle of level 1, on one
/// of its faces, in its corner (three faces), along a domain edge with all levels sharing it, a
/// one-cell slab across level 1, and coinciding with level 1.
inline std::vector<Layout> threeLevelLayouts() {
  std::vector<Layout> v;
  const std::pair<int, int> ratios[] = {{2, 2}, {3, 3}, {4, 4}, {2, 4}, {4, 3}, {3, 2}};
  for (const auto &[r1, r2] : ratios) {
    const double f = 1.0 / r1;
    const std::string s = " r=" + std::to_string(r1) + "," + std::to_string(r2);
    const BoxSpec mid{{1, 1, 1, 5, 4, 3}, r1};
    v.push_back({"middle" + s, {6, 5, 4}, {mid, {{2 + f, 2, 2 - f, 4, 3 - f, 2 + f}, r2}}});
    v.push_back({"parent face" + s, {6, 5, 4}, {mid, {{1, 2, 1 + f, 2 + f, 3, 2}, r2}}});
    v.push_back({"parent corner" + s, {6, 5, 4}, {mid, {{4 - f, 3, 2, 5, 4, 3}, r2}}});
    v.push_back(
        {"domain edge" + s, {6, 5, 4}, {{{0, 0, 1, 3, 5, 4}, r1}, {{0, 2, 2, 2, 5, 4}, r2}}});
    v.push_back({"slab" + s, {6, 5, 4}, {mid, {{3, 1, 1, 3 + f, 4, 3}, r2}}});
    v.push_back({"coincident" + s, {6, 5, 4}, {mid, mid}});
    v.back().boxes[1].ratio = r2;
  }
  return v;
}

/// A random particle inside the domain: cell-filling, anywhere, straddling a box face, or
/// covering a box corner (and so three faces and edges); half-sizes from 0.05 of a cell of any
/// level up to a quarter of a level-0 cell, cubes or not.
inline void drawParticle(const Lattice3 &g, std::mt19937_64 &rng, double *x, double *l) {
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  auto U = [&] { return uni(rng); };
  const Box3 &Dm = g.levels[0].box;
  const double h0 = g.h0(), lmax = 0.25 * h0;
  const int K = static_cast<int>(g.levels.size());
  bool inside = false;
  while (!inside) {
    const double lc =
        U() < 0.3 ? lmax * (0.5 + 0.5 * U())
                  : g.levels[std::min(K - 1, static_cast<int>(U() * K))].h * (0.05 + 0.95 * U());
    for (int a = 0; a < D; ++a)
      l[a] = std::min(lmax, U() < 0.5 ? lc : lc * std::exp(std::log(2.0) * (2 * U() - 1)));
    const double m = U();
    const Level3 &B = g.levels[K > 1 ? 1 + static_cast<int>(U() * (K - 1)) % (K - 1) : 0];
    if (m < 0.1) { // one of n^3 particles filling a leaf cell
      for (int a = 0; a < D; ++a)
        x[a] = Dm[a] + U() * (Dm[D + a] - Dm[a]);
      const Level3 &L = g.levels[g.leafLevelAt(x)];
      const int n = 1 + static_cast<int>(3 * U());
      const double hc = L.h / n;
      for (int a = 0; a < D; ++a) {
        x[a] = L.box[a] + (std::floor((x[a] - L.box[a]) / hc) + 0.5) * hc;
        l[a] = 0.5 * hc;
      }
    } else if (m < 0.3) {
      for (int a = 0; a < D; ++a)
        x[a] = Dm[a] + l[a] + U() * (Dm[D + a] - Dm[a] - 2 * l[a]);
    } else if (m < 0.65) { // straddling a face of a refined box
      const int ax = static_cast<int>(3 * U()) % 3, side = U() < 0.5 ? 0 : D;
      for (int a = 0; a < D; ++a)
        x[a] = a == ax ? B.box[side + a] + (2 * U() - 1) * (l[a] + 0.02 * h0)
                       : B.box[a] - 0.5 * h0 + U() * (B.box[D + a] - B.box[a] + h0);
    } else { // covering a corner of a refined box
      for (int a = 0; a < D; ++a)
        x[a] = B.box[(U() < 0.5 ? 0 : D) + a] + (2 * U() - 1) * (l[a] + 0.02 * h0);
    }
    inside = true;
    for (int a = 0; a < D; ++a)
      inside = inside && x[a] - l[a] >= Dm[a] + 1e-9 * h0 && x[a] + l[a] <= Dm[D + a] - 1e-9 * h0;
  }
}

} // namespace gimp::test3d
