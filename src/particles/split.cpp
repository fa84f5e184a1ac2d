// Splitting particles where a level box moved over them (particles/split.hpp).
#include "gimp/particles/split.hpp"

#include "gimp/core/errors.hpp"
#include "gimp/grid/cpdi_cells.hpp"
#include "gimp/particles/swarm.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace gimp {

namespace {

/// A particle to split: its index on this rank and its parts along each axis.
template <int D> struct SplitPlan {
  PetscInt k;
  std::array<int, D> r;
  int parts() const {
    int n = 1;
    for (int a = 0; a < D; ++a)
      n *= r[a];
    return n;
  }
};

/// The parts of particle k along each axis, or none (all 1).
template <int D>
std::array<int, D> partsOf(const Scene<D> &sc, const ParticleView<D> &p, PetscInt k) {
  std::array<int, D> r;
  r.fill(1);
  const auto b = static_cast<size_t>(p.id[k] / sc.idSlots);
  if (b >= sc.bodies.size()) return r;
  if constexpr (D == 2)
    if (!sc.bodies[b].file.empty()) return r; // a particle file's sizes are its own
  for (int a = 0; a < D; ++a)
    if ((p.trac && p.trac[D * k + a] >= 0) || (p.dbc && p.dbc[D * k + a] >= 0)) return r;
  const double *l0 = p.l0 + D * k;
  double box = D == 2 ? sc.materialOf(p.id[k]).thickness : 1.0;
  for (int a = 0; a < D; ++a)
    box *= 2.0 * l0[a];
  if (std::fabs(p.V0[k] - box) > 1e-9 * box) return r; // a cut cell
  const double n = std::round(std::pow(static_cast<double>(sc.bodies[b].ppc), 1.0 / D));
  const double half = sc.cellSizeAt(p.x + D * k) / (2.0 * n);
  std::array<int, D> q;
  for (int a = 0; a < D; ++a) {
    const double ratio = l0[a] / half, whole = std::round(ratio);
    if (whole < 1 || std::fabs(ratio - whole) > 1e-6 * whole) return r;
    q[a] = static_cast<int>(whole);
  }
  return q;
}

/// Part j's coordinate in [-1, 1] along an axis cut into r parts: its centre.
inline double partCentre(int j, int r) {
  return (2.0 * j + 1.0) / r - 1.0;
}

/// The bi/trilinear map of 2^D corners (cpdi::cornerSign order) at xi.
template <int D> void mapCorners(const double *c, const double *xi, double *out) {
  for (int a = 0; a < D; ++a)
    out[a] = 0;
  for (int q = 0; q < (1 << D); ++q) {
    double N = 1;
    for (int a = 0; a < D; ++a)
      N *= 0.5 * (1.0 + cpdi::cornerSign<D>(q, a) * xi[a]);
    for (int a = 0; a < D; ++a)
      out[a] += N * c[D * q + a];
  }
}

/// The ids of the new parts of every plan of every rank (in the order of their first part's id):
/// returns, for this rank's plans in order, the first new id (the others count down from it).
template <int D>
PetscErrorCode newIds(MPI_Comm comm, const Scene<D> &sc, const ParticleView<D> &p,
                      const std::vector<SplitPlan<D>> &plans, SplitIds &ids,
                      std::vector<PetscInt64> &first) {
  std::vector<PetscInt64> mine;
  for (const SplitPlan<D> &pl : plans)
    mine.insert(mine.end(), {p.id[pl.k], static_cast<PetscInt64>(pl.parts() - 1)});
  PetscMPIInt size = 1;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(static_cast<size_t>(size)), offsets(static_cast<size_t>(size) + 1, 0);
  PetscCallMPI(MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm));
  for (int r = 0; r < size; ++r)
    offsets[r + 1] = offsets[r] + counts[r];
  std::vector<PetscInt64> all(static_cast<size_t>(offsets[size]));
  PetscCallMPI(MPI_Allgatherv(mine.data(), count, MPI_INT64_T, all.data(), counts.data(),
                              offsets.data(), MPI_INT64_T, comm));
  std::vector<std::pair<PetscInt64, PetscInt64>> parents; // (id, new parts), every rank's
  for (size_t q = 0; q + 1 < all.size(); q += 2)
    parents.emplace_back(all[q], all[q + 1]);
  std::sort(parents.begin(), parents.end());
  std::vector<std::pair<PetscInt64, PetscInt64>> firstOf; // (id, first new id)
  for (const auto &[id, extra] : parents) {
    const auto b = static_cast<size_t>(id / sc.idSlots);
    const PetscInt64 top = static_cast<PetscInt64>(b + 1) * sc.idSlots - 1;
    firstOf.emplace_back(id, top - ids.used[b]);
    ids.used[b] += extra;
    if (top - ids.used[b] <= ids.seededTop[b]) // the same on every rank
      throw InputError("body " + std::to_string(b) +
                       ": the particle ids left above its seeded ones are used up by the "
                       "particles split where level boxes moved (-gimp_levelK_follow); give a "
                       "smaller margin or a larger box");
  }
  first.clear();
  for (const SplitPlan<D> &pl : plans)
    first.push_back(
        std::lower_bound(firstOf.begin(), firstOf.end(), std::make_pair(p.id[pl.k], PetscInt64{0}))
            ->second);
  return PETSC_SUCCESS;
}

/// The largest seeded id of each body (every rank's particles).
template <int D>
PetscErrorCode seededTops(MPI_Comm comm, const Scene<D> &sc, const ParticleView<D> &p,
                          SplitIds &ids) {
  const size_t nb = std::max<size_t>(sc.bodies.size(), 1);
  std::vector<PetscInt64> top(nb, -1);
  for (PetscInt k = 0; k < p.n; ++k) {
    const auto b = std::min(static_cast<size_t>(p.id[k] / sc.idSlots), nb - 1);
    top[b] = std::max(top[b], p.id[k]);
  }
  ids.seededTop.assign(nb, -1);
  PetscCallMPI(MPI_Allreduce(top.data(), ids.seededTop.data(), static_cast<int>(nb), MPI_INT64_T,
                             MPI_MAX, comm));
  ids.used.assign(nb, 0);
  return PETSC_SUCCESS;
}

/// Particle k as part j (multi-index) of the parent whose state is in `parent` (a copy of the
/// parent's view row: x, X0, l, l0, F, corners) with parts r.
template <int D> struct ParentGeometry {
  std::array<double, D> x, X0, l, l0;
  std::array<double, D * D> F;
  std::array<double, D *(1 << D)> corners;
  double m, V, V0;
};

template <int D>
void placePart(const ParentGeometry<D> &g, const std::array<int, D> &r, const std::array<int, D> &j,
               ParticleView<D> &p, PetscInt k) {
  double n = 1;
  for (int a = 0; a < D; ++a)
    n *= r[a];
  double xi[D], d[D];
  for (int a = 0; a < D; ++a) {
    xi[a] = partCentre(j[a], r[a]);
    d[a] = g.l0[a] * xi[a]; // the part's centre from the parent's, initially
    p.X0[D * k + a] = g.X0[a] + d[a];
    p.l0[D * k + a] = g.l0[a] / r[a];
  }
  p.m[k] = g.m / n;
  p.V[k] = g.V / n;
  p.V0[k] = g.V0 / n;
  if (p.corners) { // the bi/trilinear map of the corners, moved as the parent's centre is
    double zero[D] = {}, centre[D], at[D];
    mapCorners<D>(g.corners.data(), zero, centre);
    mapCorners<D>(g.corners.data(), xi, at);
    for (int a = 0; a < D; ++a)
      p.x[D * k + a] = at[a] + (g.x[a] - centre[a]);
    for (int q = 0; q < (1 << D); ++q) {
      double c[D], cq[D];
      for (int a = 0; a < D; ++a)
        c[a] = xi[a] + cpdi::cornerSign<D>(q, a) / r[a];
      mapCorners<D>(g.corners.data(), c, cq);
      for (int a = 0; a < D; ++a)
        p.corners[D * ((1 << D) * k + q) + a] = cq[a] + (g.x[a] - centre[a]);
    }
    for (int a = 0; a < D; ++a) { // the half-sizes: the corners' reach (tracking.hpp)
      double reach = 0;
      for (int q = 0; q < (1 << D); ++q)
        reach = std::max(reach, std::fabs(p.corners[D * ((1 << D) * k + q) + a] - p.x[D * k + a]));
      p.l[D * k + a] = reach;
    }
  } else { // F carries the initial offset to the current configuration
    for (int a = 0; a < D; ++a) {
      double dx = 0;
      for (int b = 0; b < D; ++b)
        dx += g.F[D * a + b] * d[b];
      p.x[D * k + a] = g.x[a] + dx;
      p.l[D * k + a] = g.l[a] / r[a];
    }
  }
}

} // namespace

template <int D>
PetscErrorCode splitParticles(MPI_Comm comm, const Scene<D> &sc, DM sw, SplitIds &ids,
                              PetscInt64 &added) {
  ParticleView<D> p;
  PetscCall(p.get(sw));
  if (ids.seededTop.empty()) PetscCall(seededTops(comm, sc, p, ids));
  std::vector<SplitPlan<D>> plans;
  std::vector<PetscInt> from; // the particle each new one copies
  for (PetscInt k = 0; k < p.n; ++k) {
    const std::array<int, D> r = partsOf(sc, p, k);
    SplitPlan<D> pl{k, r};
    if (pl.parts() < 2) continue;
    plans.push_back(pl);
    from.insert(from.end(), static_cast<size_t>(pl.parts() - 1), k);
  }
  std::vector<PetscInt64> first;
  PetscCall(newIds(comm, sc, p, plans, ids, first));
  const PetscInt n0 = p.n;
  PetscCall(p.restore(sw));
  PetscCall(appendCopies<D>(sw, from));
  PetscCall(p.get(sw));
  PetscInt next = n0;
  for (size_t q = 0; q < plans.size(); ++q) {
    const SplitPlan<D> &pl = plans[q];
    const PetscInt k = pl.k;
    ParentGeometry<D> g;
    for (int a = 0; a < D; ++a) {
      g.x[a] = p.x[D * k + a];
      g.X0[a] = p.X0[D * k + a];
      g.l[a] = p.l[D * k + a];
      g.l0[a] = p.l0[D * k + a];
    }
    std::copy(p.F + D * D * k, p.F + D * D * (k + 1), g.F.begin());
    if (p.corners)
      std::copy(p.corners + D * (1 << D) * k, p.corners + D * (1 << D) * (k + 1),
                g.corners.begin());
    g.m = p.m[k];
    g.V = p.V[k];
    g.V0 = p.V0[k];
    std::array<int, D> j{};
    for (int part = 0; part < pl.parts(); ++part) {
      int rest = part;
      for (int a = 0; a < D; ++a) {
        j[a] = rest % pl.r[a];
        rest /= pl.r[a];
      }
      const PetscInt at = part == 0 ? k : next++;
      placePart<D>(g, pl.r, j, p, at);
      if (part > 0) p.id[at] = first[q] - (part - 1);
    }
  }
  PetscCall(p.restore(sw));
  PetscInt64 mine = static_cast<PetscInt64>(from.size());
  PetscCallMPI(MPI_Allreduce(&mine, &added, 1, MPI_INT64_T, MPI_SUM, comm));
  return PETSC_SUCCESS;
}

template PetscErrorCode splitParticles<2>(MPI_Comm, const Scene<2> &, DM, SplitIds &, PetscInt64 &);
template PetscErrorCode splitParticles<3>(MPI_Comm, const Scene<3> &, DM, SplitIds &, PetscInt64 &);

} // namespace gimp
