// Particle -> node weights of GIMP (Eq. 15) in compressed rows, for any dimension D.
//
// Entries start[k] .. start[k+1]-1 belong to particle k; each names a slot of the window's
// nodal arrays (a window node: one velocity field per node today; see docs/architecture.md for
// how a second field at cracked nodes adds slots) and carries the 1D weights w[d] and their
// derivatives g[d] along every axis d. The weight is their product (Eq. 11) and the gradient's
// component a is g[a] times the other axes' w. CPDI weights (Grid::buildCpdiStencils) are not
// tensor products: with `general` set an entry holds its weight sw, its gradient sg[a] and the
// point shape function of the node at each of the particle's 2^D corners, cw[2^D e + c] (for the
// particle's edges). weight(e) and gradient(e) are the only way kernels read either kind. The
// arrays keep their capacity between steps: only the first start[n] entries are valid.
#pragma once

#include "gimp/core/petsc_compat.hpp"
#include "gimp/core/tensor.hpp"

#include <petscsys.h>

#include <algorithm>
#include <array>
#include <vector>

namespace gimp {

template <int D> struct Stencils {
  std::vector<PetscInt> start;
  std::vector<PetscInt> node;
  std::array<std::vector<double>, D> w, g;
  bool general = false;
  std::vector<double> sw, cw;
  std::array<std::vector<double>, D> sg;

  double weight(PetscInt e) const {
    if (general) return sw[e];
    double s = w[0][e];
    for (int d = 1; d < D; ++d)
      s *= w[d][e];
    return s;
  }
  Vector<D> gradient(PetscInt e) const {
    Vector<D> r;
    if (general) {
      for (int a = 0; a < D; ++a)
        r[a] = sg[a][e];
      return r;
    }
    for (int a = 0; a < D; ++a) {
      double s = g[a][e];
      for (int d = 0; d < D; ++d)
        if (d != a) s *= w[d][e];
      r[a] = s;
    }
    return r;
  }
  /// Make room for at least `want` entries, growing by half at least.
  void reserve(size_t want) {
    if (node.size() >= want) return;
    const size_t cap = std::max(want, node.size() + node.size() / 2);
    node.resize(cap);
    for (int d = 0; d < D; ++d) {
      w[d].resize(cap);
      g[d].resize(cap);
    }
  }
  /// The same for general entries (weights, gradients and corner values).
  void reserveGeneral(size_t want) {
    if (sw.size() >= want) return;
    const size_t cap = std::max(want, sw.size() + sw.size() / 2);
    node.resize(std::max(node.size(), cap));
    sw.resize(cap);
    cw.resize((size_t{1} << D) * cap);
    for (int d = 0; d < D; ++d)
      sg[d].resize(cap);
  }
};

} // namespace gimp
