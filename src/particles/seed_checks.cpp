// The checks of the seeded particles (see seedParticles): every body holds some, every
// traction and penalty condition reaches a particle, every particle lies inside the grid.
#include "gimp/particles/seed.hpp"

#include <algorithm>
#include <climits>
#include <string>
#include <vector>

namespace gimp {

namespace {

template <int D> std::string boxText(const BoxOf<D> &b) {
  std::string r;
  for (int i = 0; i < 2 * D; ++i)
    r += (i ? "," : "") + formatNumber(b[i]);
  return r;
}

/// The value of the option that gave a body's shape, as written in error lines: a plane body's
/// file or bounding box, a solid's box.
std::string shapeValue(const Body<2> &b) {
  return b.file.empty() ? boxText<2>(b.box) : b.file;
}
std::string shapeValue(const Body<3> &b) {
  return b.file.empty() ? boxText<3>(b.box) : b.file;
}

/// Every traction and penalty condition reaches some particle edge (2D) or face (3D)
/// (collective).
template <int D>
PetscErrorCode checkFacesReached(MPI_Comm comm, const Scene<D> &sc, const ParticleView<D> &p) {
  const size_t nt = sc.tractions.size(), nd = sc.dbcs.size();
  std::vector<PetscInt64> hits(nt + nd, 0), gHits(nt + nd, 0);
  for (PetscInt k = 0; k < p.n && p.trac; ++k)
    for (int a = 0; a < D; ++a) {
      if (p.trac[D * k + a] >= 0) ++hits[p.trac[D * k + a]];
      if (p.dbc[D * k + a] >= 0) ++hits[nt + p.dbc[D * k + a]];
    }
  if (!hits.empty())
    PetscCallMPI(MPI_Allreduce(hits.data(), gHits.data(), static_cast<int>(hits.size()),
                               MPI_INT64_T, MPI_SUM, comm));
  for (size_t q = 0; q < gHits.size(); ++q) {
    if (gHits[q] != 0) continue;
    const bool isTraction = q < nt;
    const Face<D> &seg = isTraction ? static_cast<const Face<D> &>(sc.tractions[q])
                                    : static_cast<const Face<D> &>(sc.dbcs[q - nt]);
    const std::string name =
        (isTraction ? "gimp_traction" : "gimp_dbc") + std::to_string(isTraction ? q : q - nt);
    const char *sides[] = {"left", "right", "bottom", "top", "back", "front"};
    throw InputError(
        "option -" + name + "_side " + sides[seg.side] + ": no particle " +
        (D == 2 ? "edge" : "face") + " of body " + std::to_string(seg.body) + " lies on that side" +
        (seg.hasRange ? " within -" + name + "_range" : "") + (D == 3 ? " (or its disk)" : "") +
        " (particles fill whole sub-cells: put the body's " + (D == 2 ? "edges" : "faces") +
        " on grid " + (D == 2 ? "lines" : "planes") + ")");
  }
  return PETSC_SUCCESS;
}

} // namespace

template <int D>
PetscErrorCode checkSeeding(MPI_Comm comm, const Scene<D> &sc, const Grid<D> &grid,
                            const ParticleView<D> &p, PetscInt64 &count, double &meanMass) {
  const PetscInt64 slots = bodyIdSlots<D>(grid);
  std::vector<PetscInt64> mine(sc.bodies.size(), 0), total(sc.bodies.size(), 0);
  double msum = 0, mtot = 0;
  for (PetscInt k = 0; k < p.n; ++k) {
    ++mine[p.id[k] / slots];
    msum += p.m[k];
  }
  PetscCallMPI(MPI_Allreduce(mine.data(), total.data(), static_cast<int>(mine.size()), MPI_INT64_T,
                             MPI_SUM, comm));
  PetscCallMPI(MPI_Allreduce(&msum, &mtot, 1, MPI_DOUBLE, MPI_SUM, comm));
  count = 0;
  for (size_t b = 0; b < total.size(); ++b) {
    if (total[b] == 0)
      throw InputError("option -gimp_body" + std::to_string(b) + "_" + sc.bodies[b].shapeOption +
                       " " + shapeValue(sc.bodies[b]) +
                       ": the body holds no particle (its cells are all removed by holes "
                       "or it is thinner than a particle); enlarge it or refine -gimp_h");
    count += total[b];
  }
  meanMass = mtot / static_cast<double>(count);
  PetscCall(checkFacesReached(comm, sc, p));
  // Inside; on the edge is warned of, in 2D and 3D alike: a particle whose domain ends on the
  // grid's edge deforms past it (where there are no nodes) within a few hundred steps of any
  // deformation, even on a roller there; a body at rest may fill the grid (the paper's Fig. 2),
  // so it is not refused. A body flush with the edge whose particles' domains end past it by
  // round-off (x + l = 1.0000000000000002 for an edge at 1) is on the edge, not outside: the
  // same tolerance as the run's check (Step::firstBadParticle, 1e-8 h0).
  const double margin = 1e-6 * sc.h, roundoff = 1e-8 * sc.h;
  PetscInt64 outside = INT64_MAX, gOutside = INT64_MAX, onEdge = INT64_MAX, gOnEdge = INT64_MAX;
  const BoxOf<D> &d = sc.domain;
  for (PetscInt k = 0; k < p.n; ++k) {
    bool out = false, edge = false;
    for (int a = 0; a < D; ++a) {
      const double lo = p.x[D * k + a] - p.l[D * k + a], hi = p.x[D * k + a] + p.l[D * k + a];
      out = out || lo < d[a] - roundoff || hi > d[D + a] + roundoff;
      edge = edge || lo < d[a] + margin || hi > d[D + a] - margin;
    }
    if (out)
      outside = std::min(outside, p.id[k]);
    else if (edge)
      onEdge = std::min(onEdge, p.id[k]);
  }
  PetscCallMPI(MPI_Allreduce(&outside, &gOutside, 1, MPI_INT64_T, MPI_MIN, comm));
  PetscCallMPI(MPI_Allreduce(&onEdge, &gOnEdge, 1, MPI_INT64_T, MPI_MIN, comm));
  if (gOutside != INT64_MAX)
    throw InputError("option -gimp_domain " + boxText<D>(sc.domain) + ": particle " +
                     std::to_string(gOutside) + " of body " + std::to_string(gOutside / slots) +
                     " is not inside the grid; enlarge the domain or -gimp_pad");
  if (gOnEdge != INT64_MAX) // (a body at rest may fill the grid: the paper's Fig. 2)
    PetscCall(PetscPrintf(comm,
                          "gimp: warning: -gimp_domain %s: body %lld reaches the grid's edge "
                          "(particle %lld): if it deforms it will pass the edge, where there are "
                          "no nodes, and stop the run; leave at least a cell between the bodies "
                          "and the domain's edges (a symmetry roller goes on the body's edge "
                          "inside the domain; the default domain pads -gimp_pad cells)\n",
                          boxText<D>(sc.domain).c_str(), static_cast<long long>(gOnEdge / slots),
                          static_cast<long long>(gOnEdge)));
  return PETSC_SUCCESS;
}

#define GIMP_INSTANTIATE(D)                                                                        \
  template PetscErrorCode checkSeeding<D>(MPI_Comm, const Scene<D> &, const Grid<D> &,             \
                                          const ParticleView<D> &, PetscInt64 &, double &);
GIMP_INSTANTIATE(2)
GIMP_INSTANTIATE(3)
#undef GIMP_INSTANTIATE

} // namespace gimp
