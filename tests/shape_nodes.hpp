// Shared helpers of the shape-function tests (test_shape_values.cpp, test_shape_gradients.cpp):
// 1D node sets with their influence zones, a particle's weights on them and the sampled zones.
#pragma once

#include "gimp/grid/shape.hpp"

#include <utility>
#include <vector>

namespace gimp::test {

/// A 1D set of nodes: positions and influence zones [L-, L+].
struct Nodes {
  std::vector<double> x, Lm, Lp;
  int size() const { return static_cast<int>(x.size()); }
  double lo() const { return x.front(); }
  double hi() const { return x.back(); }
};

/// n nodes at i h with zones h, and a zero zone on the outer side of the two edge nodes (as on
/// the simulation grid).
inline Nodes uniformNodes(int n, double h) {
  Nodes g;
  for (int i = 0; i < n; ++i) {
    g.x.push_back(i * h);
    g.Lm.push_back(i > 0 ? h : 0.0);
    g.Lp.push_back(i + 1 < n ? h : 0.0);
  }
  return g;
}

/// Nodes at increasing positions; each zone is the distance to the next node on that side
/// (zero beyond the first and last nodes).
inline Nodes nodesAt(const std::vector<double> &x) {
  Nodes g;
  g.x = x;
  const int n = static_cast<int>(x.size());
  for (int i = 0; i < n; ++i) {
    g.Lm.push_back(i > 0 ? x[i] - x[i - 1] : 0.0);
    g.Lp.push_back(i + 1 < n ? x[i + 1] - x[i] : 0.0);
  }
  return g;
}

/// A refined 1D mesh: two coarse cells of size r, four fine cells of size 1 and, if
/// coarseAfter, two coarse cells again. For r = 2: nodes 0, 2, 4, 5, 6, 7, 8 (, 10, 12).
inline Nodes refinedNodes(int r, bool coarseAfter) {
  std::vector<double> x = {0.0, 1.0 * r, 2.0 * r};
  for (int k = 1; k <= 4; ++k)
    x.push_back(2.0 * r + k);
  if (coarseAfter) {
    x.push_back(3.0 * r + 4);
    x.push_back(4.0 * r + 4);
  }
  return nodesAt(x);
}

/// Weights and gradients of a particle (centre xp, half-size l) at every node.
inline void particleWeights(const Nodes &g, double xp, double l, std::vector<double> &w,
                            std::vector<double> &dw) {
  w.assign(g.size(), 0.0);
  dw.assign(g.size(), 0.0);
  for (int i = 0; i < g.size(); ++i) {
    w[i] = shape::weight(xp - g.x[i], l, g.Lm[i], g.Lp[i]);
    dw[i] = shape::weightGradient(xp - g.x[i], l, g.Lm[i], g.Lp[i]);
  }
}

/// Indices of the nodes where a particle has a nonzero weight or gradient.
inline std::vector<int> support(const std::vector<double> &w, const std::vector<double> &dw) {
  std::vector<int> idx;
  for (int i = 0; i < static_cast<int>(w.size()); ++i)
    if (w[i] != 0.0 || dw[i] != 0.0) idx.push_back(i);
  return idx;
}

/// Smallest particle half-size (in units of h) of the random identity checks. The weights are
/// computed from the particle's interval ends, so their round-off grows like eps h / l; much
/// smaller particles are checked separately with a tolerance scaled by h / l.
constexpr double kMinHalfSize = 1e-3;

/// Zone pairs [L-, L+] in units of h: equal zones, the transition-node zones of 2:1, 3:1 and
/// 4:1 refinement on either side, and the edge nodes with a zero zone outside the domain.
inline const std::vector<std::pair<double, double>> kZones = {
    {1, 1}, {2, 1}, {1, 2},   {1, 0.5}, {0.5, 1}, {3, 1}, {1, 3},
    {4, 1}, {1, 4}, {2, 0.5}, {0, 1},   {1, 0},   {0, 2}, {0.5, 0}};

} // namespace gimp::test
