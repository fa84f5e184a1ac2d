// What Grid::buildCpdiStencils must give each particle, from Grid::pointShapes alone: the nodes
// of its corners' point shape functions in the order of their first appearance (corner by corner),
// and each node's weight at every corner (0 where the corner's shapes miss it). The stencil build
// has a faster path for corners among one level's regular nodes (Grid::regularCornerEntries);
// test_cpdi.cpp and test_cpdi3d.cpp hold both paths to this, bit for bit.
#pragma once

#include "gimp/grid/grid.hpp"

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

namespace gimp::test {

template <int D>
void pointShapeEntries(const Grid<D> &g, const double *c, std::vector<PetscInt> &node,
                       std::vector<double> &cw) {
  constexpr int nc = 1 << D;
  node.clear();
  cw.clear();
  std::vector<std::pair<PetscInt, double>> pts;
  for (int q = 0; q < nc; ++q) {
    pts.clear();
    g.pointShapes(c + D * q, pts);
    for (const auto &[nd, N] : pts) {
      size_t e = 0;
      while (e < node.size() && node[e] != nd)
        ++e;
      if (e == node.size()) {
        node.push_back(nd);
        cw.resize(cw.size() + nc, 0.0);
      }
      cw[nc * e + q] = N;
    }
  }
}

/// Particle k of s (corners c of all particles) has exactly pointShapeEntries' nodes and weights.
template <int D>
void expectPointShapeEntries(const Grid<D> &g, const double *c, const Stencils<D> &s, PetscInt k,
                             const std::string &name) {
  constexpr int nc = 1 << D;
  std::vector<PetscInt> node;
  std::vector<double> cw;
  pointShapeEntries<D>(g, c + D * nc * k, node, cw);
  const PetscInt e0 = s.start[k], m = s.start[k + 1] - e0;
  ASSERT_EQ(m, static_cast<PetscInt>(node.size())) << name << " particle " << k;
  for (PetscInt e = 0; e < m; ++e) {
    ASSERT_EQ(s.node[e0 + e], node[e]) << name << " particle " << k << " entry " << e;
    for (int q = 0; q < nc; ++q)
      ASSERT_EQ(s.cw[nc * (e0 + e) + q], cw[nc * e + q])
          << name << " particle " << k << " entry " << e << " corner " << q;
  }
}

} // namespace gimp::test
