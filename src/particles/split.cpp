// Splitting particles where a level box moved over them (particles/split.hpp).
#include "gimp/particles/split.hpp"

#include "gimp/core/errors.hpp"
#include "gimp/geometry/crack.hpp"
#include "gimp/geometry/crack_surface.hpp"
#include "gimp/grid/cpdi_cells.hpp"
#include "gimp/particles/swarm.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>

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

/// Whether particle k may be split or merged: a body of the scene's seeding (not a particle file,
/// whose sizes are its own), no loaded face, a whole box (not a cut cell).
template <int D> bool resizable(const Scene<D> &sc, const ParticleView<D> &p, PetscInt k) {
  const auto b = static_cast<size_t>(p.id[k] / sc.idSlots);
  if (b >= sc.bodies.size()) return false;
  if (!sc.bodies[b].file.empty()) return false;
  for (int a = 0; a < D; ++a)
    if ((p.trac && p.trac[D * k + a] >= 0) || (p.dbc && p.dbc[D * k + a] >= 0)) return false;
  double box = D == 2 ? sc.materialOf(p.id[k]).thickness : 1.0;
  for (int a = 0; a < D; ++a)
    box *= 2.0 * p.l0[D * k + a];
  return std::fabs(p.V0[k] - box) <= 1e-9 * box;
}

/// The half-size of the particles that the finest level holding particle k's centre seeds (its
/// cell over the body's particles per cell along an axis).
template <int D> double seededHalf(const Scene<D> &sc, const ParticleView<D> &p, PetscInt k) {
  const auto b = static_cast<size_t>(p.id[k] / sc.idSlots);
  const double n = std::round(std::pow(static_cast<double>(sc.bodies[b].ppc), 1.0 / D));
  return sc.cellSizeAt(p.x + D * k) / (2.0 * n);
}

/// The parts of particle k along each axis, or none (all 1).
template <int D>
std::array<int, D> partsOf(const Scene<D> &sc, const ParticleView<D> &p, PetscInt k) {
  std::array<int, D> r;
  r.fill(1);
  if (!resizable(sc, p, k)) return r;
  const double *l0 = p.l0 + D * k;
  const double half = seededHalf(sc, p, k);
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
  std::array<double, D> x, X0, l, l0, us;
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
  // With corners: the part's centre is the bi/trilinear map of the corners at its slice's centre,
  // moved as the parent's centre is from the map's (so the parts' mass centre is the parent's);
  // its corners are the map's at its slice's corners (the parts tile the parent's cell).
  if (p.corners) {
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
        p.corners[D * ((1 << D) * k + q) + a] = cq[a];
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
      g.us[a] = p.us ? p.us[D * k + a] : 0.0;
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
      if (p.us) // the crack scenes' displacement: the parent's, moved as x and X0 are
        for (int a = 0; a < D; ++a)
          p.us[D * at + a] = g.us[a] + (p.x[D * at + a] - g.x[a]) - (p.X0[D * at + a] - g.X0[a]);
      if (part > 0) p.id[at] = first[q] - (part - 1);
    }
  }
  PetscCall(p.restore(sw));
  PetscInt64 mine = static_cast<PetscInt64>(from.size());
  PetscCallMPI(MPI_Allreduce(&mine, &added, 1, MPI_INT64_T, MPI_SUM, comm));
  return PETSC_SUCCESS;
}

namespace {

/// The merge group of particle k: body, its slot of the coarser particle lattice, the parts per
/// axis (all 1 when it is not finer than the level holding it seeds).
template <int D>
std::array<std::int64_t, 2 * D + 1> mergeKey(const Scene<D> &sc, const ParticleView<D> &p,
                                             PetscInt k) {
  std::array<std::int64_t, 2 * D + 1> key{};
  key[0] = p.id[k] / sc.idSlots;
  const double half = seededHalf(sc, p, k);
  for (int a = 0; a < D; ++a) {
    const double ratio = half / p.l0[D * k + a], whole = std::round(ratio);
    if (whole < 1 || std::fabs(ratio - whole) > 1e-6 * whole) return {};
    key[1 + a] =
        static_cast<std::int64_t>(std::floor((p.X0[D * k + a] - sc.domain[a]) / (2.0 * half)));
    key[1 + D + a] = static_cast<std::int64_t>(whole);
  }
  return key;
}

/// Whether the particles of a group may merge: one level-0 cell now, no crack between them.
template <int D>
bool oneCell(const Scene<D> &sc, const ParticleView<D> &p, const std::vector<PetscInt> &g) {
  const double *x0 = p.x + D * g[0];
  for (PetscInt k : g) {
    const double *x = p.x + D * k;
    for (int a = 0; a < D; ++a)
      if (std::floor((x[a] - sc.domain[a]) / sc.h) != std::floor((x0[a] - sc.domain[a]) / sc.h))
        return false;
    for (const CrackOf<D> &c : sc.cracks)
      if (k != g[0] && cracks::crossing(c, x0, x)) return false;
  }
  return true;
}

/// The particles of group g into particle `keep` (one of them).
template <int D>
void mergeInto(const std::vector<PetscInt> &g, PetscInt keep, const std::array<int, D> &r,
               ParticleView<D> &p) {
  double m = 0, V = 0, V0 = 0, x[D] = {}, X0[D] = {}, v[D] = {}, l[D] = {}, F[D * D] = {},
         S[kStress<D>] = {}, szz = 0, eps[D] = {}, B[D * D] = {}, us[D] = {};
  for (PetscInt k : g) {
    const double mk = p.m[k], Vk = p.V[k];
    m += mk;
    V += Vk;
    V0 += p.V0[k];
    for (int a = 0; a < D; ++a) {
      x[a] += mk * p.x[D * k + a];
      X0[a] += mk * p.X0[D * k + a];
      v[a] += mk * p.v[D * k + a];
      l[a] += mk * p.l[D * k + a];
      if (p.eps) eps[a] += mk * p.eps[D * k + a];
      if (p.us) us[a] += mk * p.us[D * k + a];
    }
    for (int q = 0; q < D * D; ++q) {
      F[q] += mk * p.F[D * D * k + q];
      if (p.B) B[q] += mk * p.B[D * D * k + q];
    }
    for (int q = 0; q < kStress<D>; ++q)
      S[q] += Vk * p.s[kStress<D> * k + q];
    if (p.szz) szz += Vk * p.szz[k];
  }
  for (int a = 0; a < D; ++a) {
    x[a] /= m;
    X0[a] /= m;
    v[a] /= m;
  }
  if (p.B) // the parts' motion about the centre, as an affine moment
    for (PetscInt k : g)
      for (int i = 0; i < D; ++i)
        for (int j = 0; j < D; ++j)
          B[D * i + j] += p.m[k] * (p.v[D * k + i] - v[i]) * (p.x[D * k + j] - x[j]);
  if (p.corners) { // the slot's outer corners: each from the part at that corner
    double c[D * (1 << D)];
    for (int q = 0; q < (1 << D); ++q) {
      PetscInt best = g[0];
      double far = -1e300;
      for (PetscInt k : g) {
        double along = 0;
        for (int a = 0; a < D; ++a)
          along += cpdi::cornerSign<D>(q, a) * p.X0[D * k + a] / p.l0[D * k + a];
        if (along > far) {
          far = along;
          best = k;
        }
      }
      for (int a = 0; a < D; ++a)
        c[D * q + a] = p.corners[D * ((1 << D) * best + q) + a];
    }
    std::copy(c, c + D * (1 << D), p.corners + D * (1 << D) * keep);
  }
  p.m[keep] = m;
  p.V[keep] = V;
  p.V0[keep] = V0;
  for (int a = 0; a < D; ++a) {
    p.l0[D * keep + a] *= r[a];
    p.x[D * keep + a] = x[a];
    p.X0[D * keep + a] = X0[a];
    p.v[D * keep + a] = v[a];
    p.l[D * keep + a] = l[a] / m * r[a];
    if (p.eps) p.eps[D * keep + a] = eps[a] / m;
    if (p.us) p.us[D * keep + a] = us[a] / m;
  }
  if (p.corners)
    for (int a = 0; a < D; ++a) { // the half-sizes: the corners' reach
      double reach = 0;
      for (int q = 0; q < (1 << D); ++q)
        reach = std::max(reach,
                         std::fabs(p.corners[D * ((1 << D) * keep + q) + a] - p.x[D * keep + a]));
      p.l[D * keep + a] = reach;
    }
  for (int q = 0; q < D * D; ++q) {
    p.F[D * D * keep + q] = F[q] / m;
    if (p.B) p.B[D * D * keep + q] = B[q] / m;
  }
  for (int q = 0; q < kStress<D>; ++q)
    p.s[kStress<D> * keep + q] = S[q] / V;
  if (p.szz) p.szz[keep] = szz / V;
}

} // namespace

template <int D>
PetscErrorCode mergeParticles(MPI_Comm comm, const Scene<D> &sc, DM sw,
                              const std::vector<PetscInt64> &kept, PetscInt64 &removed) {
  ParticleView<D> p;
  PetscCall(p.get(sw));
  std::map<std::array<std::int64_t, 2 * D + 1>, std::vector<PetscInt>> groups;
  for (PetscInt k = 0; k < p.n; ++k) {
    if (!resizable(sc, p, k)) continue;
    // A kept particle stays out: its group is then short of parts, and no part of it merges.
    if (std::find(kept.begin(), kept.end(), p.id[k]) != kept.end()) continue;
    const std::array<std::int64_t, 2 *D + 1> key = mergeKey(sc, p, k);
    std::int64_t parts = 1;
    for (int a = 0; a < D; ++a)
      parts *= key[1 + D + a];
    if (parts > 1) groups[key].push_back(k);
  }
  std::vector<PetscInt> gone;
  for (const auto &[key, g] : groups) {
    std::array<int, D> r;
    std::int64_t parts = 1;
    for (int a = 0; a < D; ++a) {
      r[a] = static_cast<int>(key[1 + D + a]);
      parts *= r[a];
    }
    if (static_cast<std::int64_t>(g.size()) != parts || !oneCell(sc, p, g)) continue;
    PetscInt keep = g[0];
    for (PetscInt k : g)
      if (p.id[k] < p.id[keep]) keep = k;
    mergeInto<D>(g, keep, r, p);
    for (PetscInt k : g)
      if (k != keep) gone.push_back(k);
  }
  PetscCall(p.restore(sw));
  std::sort(gone.begin(), gone.end(), std::greater<>());
  for (PetscInt k : gone) // the last particle takes k's place: none of those left is removed
    PetscCall(DMSwarmRemovePointAtIndex(sw, k));
  PetscInt64 mine = static_cast<PetscInt64>(gone.size());
  PetscCallMPI(MPI_Allreduce(&mine, &removed, 1, MPI_INT64_T, MPI_SUM, comm));
  return PETSC_SUCCESS;
}

template PetscErrorCode mergeParticles<2>(MPI_Comm, const Scene<2> &, DM,
                                          const std::vector<PetscInt64> &, PetscInt64 &);
template PetscErrorCode mergeParticles<3>(MPI_Comm, const Scene<3> &, DM,
                                          const std::vector<PetscInt64> &, PetscInt64 &);

template PetscErrorCode splitParticles<2>(MPI_Comm, const Scene<2> &, DM, SplitIds &, PetscInt64 &);
template PetscErrorCode splitParticles<3>(MPI_Comm, const Scene<3> &, DM, SplitIds &, PetscInt64 &);

} // namespace gimp
