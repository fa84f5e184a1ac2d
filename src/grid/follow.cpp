// Level boxes that follow a point: the move of one box (grid/follow.hpp).
#include "gimp/grid/follow.hpp"

#include <cmath>

namespace gimp {

template <int D>
LatticeBox<D> followBox(const LatticeBox<D> &box, const LatticeBox<D> &parent, std::int64_t cell,
                        const double *x, double margin) {
  LatticeBox<D> b = box;
  for (int a = 0; a < D; ++a) {
    const double lo = static_cast<double>(b.lo[a]), hi = static_cast<double>(b.hi[a]);
    if (x[a] - lo < margin || hi - x[a] < margin) {
      // Whole parent cells from the centre to x (ties away from zero: a fixed rule).
      const auto shift = static_cast<std::int64_t>(std::llround((x[a] - 0.5 * (lo + hi)) / cell));
      b.lo[a] += shift * cell;
      b.hi[a] += shift * cell;
    }
    // Back inside the parent: its corners lie on the same grid lines, so the shift is whole cells.
    if (b.lo[a] < parent.lo[a]) {
      b.hi[a] += parent.lo[a] - b.lo[a];
      b.lo[a] = parent.lo[a];
    }
    if (b.hi[a] > parent.hi[a]) {
      b.lo[a] -= b.hi[a] - parent.hi[a];
      b.hi[a] = parent.hi[a];
    }
  }
  return b;
}

template LatticeBox<2> followBox<2>(const LatticeBox<2> &, const LatticeBox<2> &, std::int64_t,
                                    const double *, double);
template LatticeBox<3> followBox<3>(const LatticeBox<3> &, const LatticeBox<3> &, std::int64_t,
                                    const double *, double);

} // namespace gimp
