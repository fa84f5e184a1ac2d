// The geometry of the background grid, without PETSc objects (paper section 3), in D = 2 or 3
// dimensions.
//
// Level 0 covers the domain; level k+1 is a box inside level k, its corners on level-k grid
// lines, its cell size h_k / r with an integer ratio r >= 2. Every node lies on one integer
// lattice whose unit is the finest cell size, so activity and zones are decided exactly. A node
// shared by several levels belongs to the finest; coarse nodes covered by a finer box are
// inactive. Every active node has an influence zone per axis and side, [Lx-, Lx+, Ly-, Ly+]
// (and Lz-, Lz+ in 3D): on each side the width of the leaf cells touching it there (the
// smallest where they differ), zero outside the domain. A single uniform level is the case of
// one box.
#pragma once

#include "gimp/core/box.hpp"
#include "gimp/core/errors.hpp"
#include "gimp/core/tensor.hpp"

#include <petscsys.h>

#include <array>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

namespace gimp {

/// Integer coordinates on the finest lattice (or a level's node indices), one per axis.
template <int D> using LatticeIndex = std::array<std::int64_t, D>;

template <int D> struct Level {
  double h = 0, ih = 0;                   // cell size [m] and its reciprocal
  BoxOf<D> box{};                         // [m]
  std::array<std::int64_t, D> lo{}, hi{}; // box corners in finest-lattice units
  std::int64_t step = 1;                  // cell size in finest-lattice units
  std::array<PetscInt, D> n{};            // nodes per axis
  // This rank's window of the level (set by Grid::create): nodes [w0, w1) per axis, x fastest,
  // numbered from offset on in the window arrays of all levels.
  std::array<PetscInt, D> w0{}, w1{};
  PetscInt offset = 0;
  PetscInt wn(int a) const { return w1[a] - w0[a]; }
  PetscInt wnx() const { return wn(0); }
  /// Nodes of the window (the product of wn over the axes).
  PetscInt windowNodes() const {
    PetscInt m = 1;
    for (int a = 0; a < D; ++a)
      m *= wn(a);
    return m;
  }
  /// Lattice coordinate of node i on axis a.
  std::int64_t at(int a, std::int64_t i) const { return lo[a] + i * step; }
};

template <int D> class Lattice {
public:
  using Index = LatticeIndex<D>;

  /// Levels from level 0's cell size h0 and the boxes (boxes[0] the domain). Throws InputError
  /// naming the option -gimp_level<k>_box for a layout that is not properly nested.
  void setLevels(double h0, const std::vector<LevelBox<D>> &boxes);

  std::vector<Level<D>> levels;
  std::array<double, D> origin{}; // the domain's low corner [m]
  double unit = 0;                // finest-lattice unit [m]
  double hMin() const { return levels.back().h; }
  double h0() const { return levels.front().h; }

  // Pure geometry, in level k's node indices.
  bool nodeActive(int k, const Index &i) const;
  /// Zones of an active node: z[2a] and z[2a + 1] are the zones below and above on axis a.
  void zonesOf(int k, const Index &i, double z[2 * D]) const;
  /// Level whose leaf cell contains the point at doubled lattice coordinates a, which must not
  /// lie on a grid line; -1 outside the domain.
  int leafLevelAtDoubled(const Index &a) const;
  /// Level of the leaf cell containing the point x [m] (D coordinates).
  int leafLevelAt(const double *x) const;
  /// 2D shorthands of the two above.
  template <int E = D, std::enable_if_t<E == 2, int> = 0>
  int leafLevelAtDoubled(std::int64_t a, std::int64_t b) const {
    return leafLevelAtDoubled(Index{a, b});
  }
  template <int E = D, std::enable_if_t<E == 2, int> = 0>
  int leafLevelAt(double x, double y) const {
    const double p[2] = {x, y};
    return leafLevelAt(p);
  }
  std::int64_t activeNodes(int k) const;
  /// Index of the level-0 grid line at coordinate c on axis (0: x, 1: y, 2: z), or -1.
  PetscInt lineIndex(int axis, double c) const;
  /// Active nodes as CSV rows level,x,y,Lxm,Lxp,Lym,Lyp (3D: level,x,y,z,Lxm,...,Lzp), with the
  /// header line.
  std::string activeNodesCsv() const;
  /// Coordinate [m] of level k's node i on axis a.
  double nodeCoordinate(int k, int a, std::int64_t i) const {
    return origin[a] + static_cast<double>(levels[k].at(a, i)) * unit;
  }
};

/// Calls f(i) for every index of the box [0, n) (x fastest).
template <int D, class F> void forEachIndex(const std::array<PetscInt, D> &n, F &&f) {
  LatticeIndex<D> i{};
  for (int a = 0; a < D; ++a)
    if (n[a] <= 0) return;
  for (;;) {
    f(static_cast<const LatticeIndex<D> &>(i));
    int a = 0;
    while (a < D && ++i[a] == n[a])
      i[a++] = 0;
    if (a == D) return;
  }
}

extern template class Lattice<2>;
extern template class Lattice<3>;

} // namespace gimp
