// Internal to src/cracks: a 3D crack's front chains as the front integrals see them (front.cpp):
// the chain of consecutive front edges that holds a front point, and where a point lies seen from
// it (its nearest point, arc length, and the frame there).
#pragma once

#include "gimp/geometry/crack_surface.hpp"

#include <array>
#include <cmath>
#include <vector>

namespace gimp::cracks::chain {

using P3 = std::array<double, 3>;

inline P3 sub(const P3 &a, const P3 &b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline double dot(const P3 &a, const P3 &b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline P3 cross(const P3 &a, const P3 &b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const P3 &a) {
  return std::sqrt(dot(a, a));
}

/// The ahead direction at polygon vertex v as the advance field takes it: the mean of its two
/// edges' ahead directions where both are front edges, or where a mouth edge continues the front
/// (turning by less than 45 degrees: a curved front that the polygon continues past a body's
/// surface or a symmetry plane, where the mean is the front's normal at the surface); otherwise
/// the front edge's own (for a vertex with at least one front edge).
P3 vertexAhead(const CrackSurface &c, size_t v);

/// The chain of consecutive front edges holding front point f's edge: its edges in order, the arc
/// length at each one's start, the chain's length, and the arc length of f from the chain's start
/// [m]. A closed chain (every edge a front edge) starts at f's edge.
struct Chain {
  std::vector<int> edges;
  std::vector<double> s0;
  double length = 0, sP = 0;
  bool closed = false;
  // Per edge, for placeOf: its start, its vector and length, its frame and its vertices' ahead
  // directions (vertexAhead).
  std::vector<P3> start, vec, a, t, ahead0, ahead1;
  std::vector<double> len;
};

Chain chainOf(const CrackSurface &c, const FrontPoint &f);

/// Where a point is seen from the front: rho, the nearest point y, its arc length s from P (in
/// (-length / 2, length / 2] on a closed chain), grad s (the edge's t, or 0 at a vertex), and the
/// local frame at y (a ahead, x3 = a x n).
struct Place {
  double rho = 0, s = 0;
  P3 y{}, gradS{}, a{}, x3{};
  double dA[3][3] = {};   // d a_k / d x_j (nonzero in a vertex's wedge, where a turns)
  double curv[3][3] = {}; // (da/ds) t^T of the nearest edge, also where y is held at a vertex
};

/// The place of x seen from chain ch (placeOf in front_chain.cpp).
Place placeOf(const CrackSurface &c, const Chain &ch, const P3 &x);

} // namespace gimp::cracks::chain
