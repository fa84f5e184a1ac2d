// The geometry of the background grid, without PETSc objects (paper section 3).
//
// Level 0 covers the domain; level k+1 is a box inside level k, its corners on level-k grid
// lines, its cell size h_k / r with an integer ratio r >= 2. Every node lies on one integer
// lattice whose unit is the finest cell size, so activity and zones are decided exactly. A node
// shared by several levels belongs to the finest; coarse nodes covered by a finer box are
// inactive. Every active node has an influence zone [Lx-, Lx+, Ly-, Ly+]: on each side the width
// of the leaf cells touching it there (the smaller one where two differ), zero outside the
// domain. A single uniform level is the case of one box.
#pragma once

#include "gimp/input/scene.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace gimp {

struct Level {
  double h = 0, ih = 0;        // cell size [m] and its reciprocal
  Box box{};                   // [m]
  std::int64_t u0 = 0, v0 = 0; // lower-left corner in finest-lattice units
  std::int64_t u1 = 0, v1 = 0; // upper-right corner
  std::int64_t step = 1;       // cell size in finest-lattice units
  PetscInt M = 0, N = 0;       // nodes in x and y
  // This rank's window of the level (set by Grid::create): nodes [wi0, wi1) x [wj0, wj1),
  // numbered from offset on in the window arrays of all levels.
  PetscInt wi0 = 0, wi1 = 0, wj0 = 0, wj1 = 0;
  PetscInt offset = 0;
  PetscInt wnx() const { return wi1 - wi0; }
};

class Lattice {
public:
  /// Levels from the scene (validated there). Throws InputError for a layout that is not
  /// properly nested; the same on every rank.
  void setGeometry(const Scene &sc);

  std::vector<Level> levels;
  double x0 = 0, y0 = 0, unit = 0; // domain origin, finest-lattice unit [m]
  double hMin() const { return levels.back().h; }
  double h0() const { return levels.front().h; }

  // Pure geometry, in level k's node indices.
  bool nodeActive(int k, std::int64_t i, std::int64_t j) const;
  void zonesOf(int k, std::int64_t i, std::int64_t j, double z[4]) const;
  /// Level whose leaf cell contains the point at doubled lattice coordinates (a, b), which
  /// must not lie on a grid line; -1 outside the domain.
  int leafLevelAt2(std::int64_t a, std::int64_t b) const;
  /// Level of the leaf cell containing (x, y) [m].
  int leafLevelAt(double x, double y) const;
  std::int64_t activeNodes(int k) const;
  /// Index of the level-0 grid line at coordinate c on axis (0: x, 1: y), or -1.
  PetscInt lineIndex(int axis, double c) const;
  /// Active nodes as CSV rows level,x,y,Lxm,Lxp,Lym,Lyp (with the header line).
  std::string activeNodesCsv() const;
};

} // namespace gimp
