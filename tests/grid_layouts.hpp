// Shared helpers of the composite-grid tests (test_lattice.cpp, test_stencils.cpp,
// test_stencil_smoothness.cpp): the refined layouts they run on, scenes and grids built from
// them, a random particle sampler and the documented reasons for rejecting a layout.
#pragma once

#include "gimp/grid/grid.hpp"
#include "gimp/input/scene.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace gimp::test {

/// A refined box: corners in level-0 cells from the domain origin (fractions where they fall on
/// the parent's grid lines) and the refinement ratio to its parent.
struct BoxSpec {
  double i0, j0, i1, j1;
  int ratio;
};

struct Layout {
  std::string name;
  int nx, ny; // level-0 cells of the domain
  std::vector<BoxSpec> boxes;
};

// Domain origin and level-0 cell size that are not binary fractions, so that node coordinates
// carry round-off as in real scenes.
constexpr double kX0 = -1.3, kY0 = 0.7, kH0 = 0.37;

inline Scene<2> sceneOf(const Layout &lay, double x0 = kX0, double y0 = kY0, double h0 = kH0) {
  Scene<2> sc;
  sc.h = h0;
  sc.domain = {x0, y0, x0 + lay.nx * h0, y0 + lay.ny * h0};
  sc.levels.assign(1, LevelBox<2>{sc.domain, 1});
  for (const BoxSpec &b : lay.boxes)
    sc.levels.push_back(
        LevelBox<2>{{x0 + b.i0 * h0, y0 + b.j0 * h0, x0 + b.i1 * h0, y0 + b.j1 * h0}, b.ratio});
  return sc;
}

/// A grid from a scene given in code (plain numbers, not options).
inline Scene<2> plainScene(const BoxOf<2> &domain, double h, const std::vector<LevelBox<2>> &fine) {
  Scene<2> sc;
  sc.h = h;
  sc.domain = domain;
  sc.levels.assign(1, LevelBox<2>{domain, 1});
  sc.levels.insert(sc.levels.end(), fine.begin(), fine.end());
  return sc;
}

inline std::unique_ptr<Grid<2>> makeGrid(const Scene<2> &sc) {
  auto g = std::make_unique<Grid<2>>();
  EXPECT_EQ(static_cast<int>(g->create(PETSC_COMM_SELF, sc.h, sc.levelBoxes(), sc.cracks)), 0);
  return g;
}

/// 2-level layouts: one fine box in the middle, on the domain edge, in a domain corner, over one
/// level-0 cell and over the whole domain; ratios 2, 3 and 4.
inline std::vector<Layout> twoLevelLayouts() {
  std::vector<Layout> v;
  for (int r : {2, 3, 4}) {
    const std::string s = " r=" + std::to_string(r);
    v.push_back({"middle" + s, 10, 8, {{3, 2, 7, 6, r}}});
    v.push_back({"domain edge" + s, 10, 8, {{0, 3, 4, 8, r}}});
    v.push_back({"domain corner" + s, 10, 8, {{6, 0, 10, 3, r}}});
    v.push_back({"one cell" + s, 10, 8, {{5, 4, 6, 5, r}}});
    v.push_back({"whole domain" + s, 10, 8, {{0, 0, 10, 8, r}}});
  }
  return v;
}

/// 3-level layouts (level-2 box in level-1 cells f = 1 / r1 of a level-0 cell): in the middle of
/// level 1, on level 1's left edge, in level 1's upper-right corner, along the domain edge with
/// all three levels sharing the corner (0, 8), a one-cell strip across level 1 from its bottom to
/// its top edge, and coinciding with level 1 (a level-2 box next to level-0 cells).
inline std::vector<Layout> threeLevelLayouts() {
  std::vector<Layout> v;
  const std::pair<int, int> ratios[] = {{2, 2}, {3, 3}, {4, 4}, {2, 4}, {4, 3}, {3, 2}};
  for (const auto &[r1, r2] : ratios) {
    const double f = 1.0 / r1;
    const std::string s = " r=" + std::to_string(r1) + "," + std::to_string(r2);
    v.push_back({"middle" + s, 10, 8, {{2, 2, 8, 6, r1}, {3 + f, 3, 6, 5 - f, r2}}});
    v.push_back({"parent edge" + s, 10, 8, {{2, 2, 8, 6, r1}, {2, 3, 4 + f, 5, r2}}});
    v.push_back({"parent corner" + s, 10, 8, {{2, 2, 8, 6, r1}, {6 - f, 4, 8, 6, r2}}});
    v.push_back({"domain edge" + s, 10, 8, {{0, 0, 5, 8, r1}, {0, 2, 3, 8, r2}}});
    v.push_back({"strip" + s, 10, 8, {{2, 2, 8, 6, r1}, {4, 2, 4 + f, 6, r2}}});
    v.push_back({"coincident" + s, 10, 8, {{3, 2, 7, 6, r1}, {3, 2, 7, 6, r2}}});
  }
  return v;
}

/// The particle lies inside the domain, clear of its edges by at least 1e-9 h0. (A particle whose
/// edge lies exactly on the domain edge: GridStencils.ParticleTouchingDomainEdge.)
inline bool insideDomain(const Grid<2> &g, double x, double y, double lx, double ly) {
  const BoxOf<2> &D = g.levels[0].box;
  const double m = 1e-9 * g.h0();
  return x - lx >= D[0] + m && x + lx <= D[2] - m && y - ly >= D[1] + m && y + ly <= D[3] - m;
}

/// Random particles that exercise the composite grid: cell-filling particles (edges on grid
/// lines), particles anywhere, straddling box edges, covering box corners and around transition
/// nodes; half-sizes from 0.05 of a cell of any level up to half a level-0 cell (a coarse
/// particle that moved into a fine region; up to a whole one on request), square or not. Every
/// particle lies in the domain.
class Sampler {
public:
  Sampler(const Grid<2> &g, std::uint64_t seed) : g_(g), rng_(seed) {
    for (size_t k = 1; k < g.levels.size(); ++k) {
      const BoxOf<2> &b = g.levels[k].box;
      edges_.push_back({0, b[0], b[1], b[3]});
      edges_.push_back({0, b[2], b[1], b[3]});
      edges_.push_back({1, b[1], b[0], b[2]});
      edges_.push_back({1, b[3], b[0], b[2]});
      for (double x : {b[0], b[2]})
        for (double y : {b[1], b[3]})
          corners_.push_back({x, y});
    }
    for (PetscInt n = 0; n < g.nWindow; ++n)
      if (g.active[n] && !g.regular[n]) transition_.push_back(n);
  }

  double U() { return uni_(rng_); }
  template <class T> const T &pick(const std::vector<T> &v) {
    return v[std::min(v.size() - 1, static_cast<size_t>(U() * v.size()))];
  }

  /// A particle; half-sizes up to lmax (default: half a level-0 cell).
  void draw(double &x, double &y, double &lx, double &ly, bool cellFilling = true,
            double lmax = 0.0) {
    const BoxOf<2> &D = g_.levels[0].box;
    const double h0 = g_.h0();
    if (lmax <= 0.0) lmax = 0.5 * h0;
    const int K = static_cast<int>(g_.levels.size());
    do {
      if (U() < 0.3) {
        lx = lmax * (0.5 + 0.5 * U());
      } else {
        const Level<2> &L = g_.levels[std::min(K - 1, static_cast<int>(U() * K))];
        lx = L.h * (0.05 + 0.95 * U());
      }
      ly = U() < 0.5 ? lx : lx * std::exp(std::log(2.0) * (2.0 * U() - 1.0));
      lx = std::min(lx, lmax);
      ly = std::min(ly, lmax);
      const double m = U();
      if (m < (cellFilling ? 0.1 : 0.0)) {
        // One of n x n particles filling a leaf cell.
        x = D[0] + U() * (D[2] - D[0]);
        y = D[1] + U() * (D[3] - D[1]);
        const Level<2> &L = g_.levels[g_.leafLevelAt(x, y)];
        const int n = 1 + static_cast<int>(3 * U());
        const double hc = L.h / n;
        x = L.box[0] + (std::floor((x - L.box[0]) / hc) + 0.5) * hc;
        y = L.box[1] + (std::floor((y - L.box[1]) / hc) + 0.5) * hc;
        lx = ly = 0.5 * hc;
      } else if (m < 0.3 || edges_.empty()) {
        x = D[0] + lx + U() * (D[2] - D[0] - 2 * lx);
        y = D[1] + ly + U() * (D[3] - D[1] - 2 * ly);
      } else if (m < 0.55) { // straddling a box edge
        const auto &e = pick(edges_);
        const double along = e[2] - 0.5 * h0 + U() * (e[3] - e[2] + h0);
        if (e[0] == 0) {
          x = e[1] + (2 * U() - 1) * (lx + 0.02 * h0);
          y = along;
        } else {
          x = along;
          y = e[1] + (2 * U() - 1) * (ly + 0.02 * h0);
        }
      } else if (m < 0.75) { // covering a box corner
        const auto &c = pick(corners_);
        x = c[0] + (2 * U() - 1) * (lx + 0.02 * h0);
        y = c[1] + (2 * U() - 1) * (ly + 0.02 * h0);
      } else { // around a transition node
        const PetscInt n = pick(transition_);
        const double *z = &g_.zone[4 * n];
        x = g_.X[n] + (2 * U() - 1) * (lx + std::max(z[0], z[1]));
        y = g_.Y[n] + (2 * U() - 1) * (ly + std::max(z[2], z[3]));
      }
    } while (!insideDomain(g_, x, y, lx, ly));
  }

  /// The particle covers points of leaf cells of two levels.
  bool straddles(double x, double y, double lx, double ly) const {
    const int q = g_.leafLevelAt(x, y);
    for (double sx : {-0.999, 0.0, 0.999})
      for (double sy : {-0.999, 0.0, 0.999})
        if (g_.leafLevelAt(x + sx * lx, y + sy * ly) != q) return true;
    return false;
  }
  /// A box corner lies strictly inside the particle.
  bool coversCorner(double x, double y, double lx, double ly) const {
    for (const auto &c : corners_)
      if (std::abs(c[0] - x) < lx && std::abs(c[1] - y) < ly) return true;
    return false;
  }

private:
  const Grid<2> &g_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> uni_{0.0, 1.0};
  std::vector<std::array<double, 4>> edges_; // axis (0: line x = c), c, from, to
  std::vector<std::array<double, 2>> corners_;
  std::vector<PetscInt> transition_; // active nodes with a zone other than their level's h
};

// The documented reasons for rejecting a layout, as setLevels words them.
const char *const kOffLines = "is not on a grid line of level";
const char *const kNotInside = "(levels must be nested)";
const char *const kEmpty = "needs x1 > x0 and y1 > y0";

} // namespace gimp::test
