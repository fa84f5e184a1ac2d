// The front measures of a 3D scene: every front point's tube integrals summed over the ranks
// (measureFronts), and where and how the scene measures (frontDomain: the cell at the fronts, the
// tube radius asked for, the symmetry planes).
#include "gimp/cracks/front.hpp"

#include <cmath>

namespace gimp::cracks {

PetscErrorCode measureFronts(MPI_Comm comm, const std::vector<CrackSurface> &cracks,
                             const Material &m, const ParticleView<3> &p, double spacing,
                             const std::vector<JDomain> &tubes, double asked,
                             const std::vector<MirrorPlane> &mirrors,
                             std::vector<FrontMeasure> &out) {
  std::vector<std::pair<int, FrontPoint>> points;
  for (size_t c = 0; c < cracks.size(); ++c)
    for (const FrontPoint &f : frontPoints(cracks[c], spacing))
      points.emplace_back(static_cast<int>(c), f);
  out.clear();
  if (points.empty()) return PETSC_SUCCESS;
  PetscCheck(tubes.size() == points.size(), comm, PETSC_ERR_PLIB,
             "%zu front tubes for %zu front points", tubes.size(), points.size());
  std::vector<double> local(4 * points.size(), 0.0), global(local.size());
  // The points of one open chain together (addChainIntegrals: each particle placed once), the
  // others one by one; the points are in order (crack, then along the polygon).
  for (size_t q = 0; q < points.size();) {
    const CrackSurface &c = cracks[static_cast<size_t>(points[q].first)];
    const int start = openChainStart(c, points[q].second);
    size_t end = q + 1;
    while (start >= 0 && end < points.size() && points[end].first == points[q].first &&
           openChainStart(c, points[end].second) == start)
      ++end;
    std::vector<FrontPoint> group;
    std::vector<double> R;
    std::vector<size_t> slot;
    for (size_t i = q; i < end; ++i)
      if (tubes[i].radius > 0) {
        group.push_back(points[i].second);
        R.push_back(tubes[i].radius);
        slot.push_back(i);
      }
    if (start >= 0) {
      std::vector<double> sums(4 * group.size(), 0.0);
      addChainIntegrals(m, p, c, group, R, sums.data(), mirrors);
      for (size_t g = 0; g < group.size(); ++g)
        for (size_t j = 0; j < 4; ++j)
          local[4 * slot[g] + j] = sums[4 * g + j];
    } else {
      for (size_t g = 0; g < group.size(); ++g)
        addFrontIntegrals(m, p, c, group[g], R[g], R[g], &local[4 * slot[g]], AuxFrame::Nearest,
                          mirrors);
    }
    q = end;
  }
  PetscCallMPI(MPI_Allreduce(local.data(), global.data(), static_cast<int>(local.size()),
                             MPI_DOUBLE, MPI_SUM, comm));
  for (size_t q = 0; q < points.size(); ++q) {
    const CrackSurface &c = cracks[static_cast<size_t>(points[q].first)];
    const double R = tubes[q].radius;
    if (R > 0) {
      out.push_back(finishFront(m, c, points[q].second, R, R, &global[4 * q], mirrors));
    } else {
      FrontMeasure o;
      o.edge = points[q].second.edge;
      o.x = points[q].second.x;
      o.G = o.KI = o.KII = o.KIII = NAN;
      out.push_back(o);
    }
    out.back().crack = points[q].first;
    out.back().asked = asked;
    out.back().clipped = tubes[q].clipped;
  }
  return PETSC_SUCCESS;
}

FrontDomain frontDomain(const Scene<3> &sc) {
  FrontDomain d;
  for (const CrackSurface &c : sc.cracks) {
    const std::vector<FrontPoint> f = frontPoints(c, sc.h);
    if (!f.empty()) {
      d.at = f.front().x;
      break;
    }
  }
  d.h = frontCell(sc);
  d.R = sc.crackJRadius > 0 ? sc.crackJRadius : kJCells * d.h;
  // Symmetry planes: rollers (the normal component alone held) over a whole plane that the
  // bodies touch from one side.
  const double tol = 1e-9 * sc.h;
  for (const NodeBC<3> &b : sc.bcs) {
    const size_t a = static_cast<size_t>(b.axis);
    const bool roller = b.fix[a] && !b.fix[(a + 1) % 3] && !b.fix[(a + 2) % 3];
    if (!roller || b.hasRange || sc.bodies.empty()) continue;
    bool above = true, below = true, touches = false;
    for (const Body<3> &body : sc.bodies) {
      const double lo = body.box[a], hi = body.box[3 + a];
      above = above && lo >= b.coord - tol;
      below = below && hi <= b.coord + tol;
      touches = touches || std::fabs(lo - b.coord) <= tol || std::fabs(hi - b.coord) <= tol;
    }
    if ((above || below) && touches) d.mirrors.push_back({b.axis, b.coord});
  }
  d.spacing = frontSpacing(sc);
  return d;
}

} // namespace gimp::cracks
