#include "gimp/diagnostics/measures.hpp"
#include "gimp/cracks/geometry.hpp"

#include "gimp/diagnostics/gather.hpp"
#include "gimp/particles/swarm.hpp"
#include "gimp/physics/mms.hpp"
#include "gimp/physics/tracking.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <map>

namespace gimp {

PetscErrorCode findProbes(MPI_Comm comm, const Scene &sc, DM sw, std::vector<PetscInt64> &ids) {
  ParticleView p;
  PetscCall(p.get(sw));
  ids.clear();
  for (const Probe &pr : sc.probes) {
    double best = 1e300;
    PetscInt64 bestId = INT64_MAX;
    for (PetscInt k = 0; k < p.n; ++k) {
      const double dx = p.X0[2 * k] - pr.x[0], dy = p.X0[2 * k + 1] - pr.x[1];
      const double d2 = dx * dx + dy * dy;
      if (d2 < best || (d2 == best && p.id[k] < bestId)) {
        best = d2;
        bestId = p.id[k];
      }
    }
    double gbest = 0;
    PetscCallMPI(MPI_Allreduce(&best, &gbest, 1, MPI_DOUBLE, MPI_MIN, comm));
    PetscInt64 mine = best == gbest ? bestId : INT64_MAX, gid = 0;
    PetscCallMPI(MPI_Allreduce(&mine, &gid, 1, MPI_INT64_T, MPI_MIN, comm));
    ids.push_back(gid);
  }
  PetscCall(p.restore(sw));
  return PETSC_SUCCESS;
}

PetscErrorCode probeStates(MPI_Comm comm, DM sw, const std::vector<PetscInt64> &ids,
                           std::vector<ProbeState> &out) {
  ParticleView p;
  PetscCall(p.get(sw));
  constexpr int kCols = 8;
  std::vector<double> loc(ids.size() * kCols, 0.0), glob(ids.size() * kCols, 0.0);
  for (PetscInt k = 0; k < p.n; ++k)
    for (size_t q = 0; q < ids.size(); ++q)
      if (p.id[k] == ids[q]) {
        double *r = &loc[kCols * q];
        const auto s = tensorAt<2>(p.s, k);
        const double row[kCols] = {p.X0[2 * k],
                                   p.X0[2 * k + 1],
                                   p.x[2 * k] - p.X0[2 * k],
                                   p.x[2 * k + 1] - p.X0[2 * k + 1],
                                   s(0, 0),
                                   s(1, 1),
                                   s(0, 1),
                                   p.szz[k]};
        std::copy(row, row + kCols, r);
      }
  PetscCall(p.restore(sw));
  PetscCallMPI(MPI_Allreduce(loc.data(), glob.data(), static_cast<int>(loc.size()), MPI_DOUBLE,
                             MPI_SUM, comm));
  out.assign(ids.size(), ProbeState{});
  for (size_t q = 0; q < ids.size(); ++q) {
    const double *r = &glob[kCols * q];
    out[q].id = ids[q];
    std::copy(r, r + 2, out[q].X0);
    std::copy(r + 2, r + 4, out[q].u);
    std::copy(r + 4, r + 8, out[q].stress);
  }
  return PETSC_SUCCESS;
}

PetscErrorCode mmsErrors(MPI_Comm comm, const Scene &sc, DM sw, double t, double &linf,
                         double &rms) {
  linf = rms = 0;
  if (sc.mms == Mms::None) return PETSC_SUCCESS;
  const mms::Skb1d ex(sc);
  ParticleView p;
  PetscCall(p.get(sw));
  double loc[3] = {0, 0, 0}, glob[3];
  for (PetscInt k = 0; k < p.n; ++k) {
    const double X = p.X0[2 * k];
    const double ex_ = p.x[2 * k] - X - ex.u(X, t), ey = p.x[2 * k + 1] - p.X0[2 * k + 1];
    const double e2 = ex_ * ex_ + ey * ey;
    loc[0] = std::max(loc[0], std::sqrt(e2));
    loc[1] += e2 * p.V0[k];
    loc[2] += p.V0[k];
  }
  PetscCall(p.restore(sw));
  PetscCallMPI(MPI_Allreduce(&loc[0], &glob[0], 1, MPI_DOUBLE, MPI_MAX, comm));
  PetscCallMPI(MPI_Allreduce(&loc[1], &glob[1], 2, MPI_DOUBLE, MPI_SUM, comm));
  linf = glob[0];
  rms = std::sqrt(glob[1] / glob[2]);
  return PETSC_SUCCESS;
}

namespace {

/// On rank 0: the separation measure over all particles' rows (id, X0, centre, l, l0).
void separationOfRows(const std::vector<double> &all, int kCols, double q,
                      const std::vector<Crack> &cracks, double res[2]) {
  const size_t n = all.size() / kCols;
  auto key = [q](double x, double y) {
    return std::make_pair(std::llround(x / q), std::llround(y / q));
  };
  std::map<std::pair<long long, long long>, size_t> at;
  double lo = 1e300, hi = -1e300, lo0 = 1e300, hi0 = -1e300;
  for (size_t i = 0; i < n; ++i) {
    const double *r = &all[i * kCols];
    at[key(r[1], r[2])] = i;
    lo = std::min(lo, r[3] - r[5]);
    hi = std::max(hi, r[3] + r[5]);
    lo0 = std::min(lo0, r[1] - r[7]);
    hi0 = std::max(hi0, r[1] + r[7]);
  }
  double worst = 0;
  for (size_t i = 0; i < n; ++i) {
    const double *r = &all[i * kCols];
    for (int d = 0; d < 2; ++d) {
      const auto it = at.find(key(r[1] + (d == 0) * 2 * r[7], r[2] + (d == 1) * 2 * r[8]));
      if (it == at.end()) continue;
      const double *o = &all[it->second * kCols];
      if (o[7 + d] != r[7 + d]) continue; // neighbours of another size (another level)
      if (std::any_of(cracks.begin(), cracks.end(), [&](const Crack &c) {
            return cracks::crossing(c, r[1], r[2], o[1], o[2]) != 0;
          }))
        continue; // a crack between them
      const double g = ((o[3 + d] - o[5 + d]) - (r[3 + d] + r[5 + d])) / (2.0 * r[7 + d]);
      worst = std::max(worst, g);
    }
  }
  res[0] = worst;
  res[1] = (hi - lo) / (hi0 - lo0) - 1.0;
}

} // namespace

PetscErrorCode separation(MPI_Comm comm, const Lattice &grid, DM sw,
                          const std::vector<Crack> &cracks, double &gap, double &strain) {
  ParticleView p;
  PetscCall(p.get(sw));
  constexpr int kCols = 9;
  std::vector<double> loc(static_cast<size_t>(p.n) * kCols);
  for (PetscInt k = 0; k < p.n; ++k) {
    double *r = &loc[static_cast<size_t>(k) * kCols];
    r[0] = static_cast<double>(p.id[k]);
    for (int d = 0; d < 2; ++d) {
      // The particle's domain: centred on the material point, or the corners' rectangle.
      r[1 + d] = p.X0[2 * k + d];
      r[3 + d] = p.hasCorners ? tracking::cornerBoxCentre(&p.corners[8 * k], d) : p.x[2 * k + d];
      r[5 + d] = p.l[2 * k + d];
      r[7 + d] = p.l0[2 * k + d];
    }
  }
  PetscCall(p.restore(sw));
  std::vector<double> all;
  PetscCall(gatherToRoot(comm, loc, all));
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  double res[2] = {0, 0};
  // Initial positions lie on a lattice of step unit / 512.
  if (rank == 0) separationOfRows(all, kCols, grid.unit / 512.0, cracks, res);
  PetscCallMPI(MPI_Bcast(res, 2, MPI_DOUBLE, 0, comm));
  gap = res[0];
  strain = res[1];
  return PETSC_SUCCESS;
}

} // namespace gimp
