// Boxes and points in D = 2 or 3 dimensions, as the scene and the grid both take them.
#pragma once

#include <array>

namespace gimp {

/// A point or a vector of D coordinates [m, m/s, Pa, ...].
template <int D> using Coords = std::array<double, D>;

/// A box in D dimensions: the low corner's D coordinates, then the high corner's. For D = 2:
/// x0, y0, x1, y1; for D = 3: x0, y0, z0, x1, y1, z1.
template <int D> using BoxOf = std::array<double, 2 * D>;

/// One grid level as the scene gives it: its box (level 0: the domain) and its ratio to the
/// parent level (1 for level 0).
template <int D> struct LevelBox {
  BoxOf<D> box{};
  int ratio = 1;
};

} // namespace gimp
