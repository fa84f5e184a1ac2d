// The check after every step: a particle that is not finite, left the grid, or is inverted or
// larger than a level-0 cell stops the run on every rank (the first such particle of the lowest
// failing rank is named, in one line); one reduction also counts the particles leaving their rank's
// cells (the next step's migration) and agrees on SIGINT / SIGTERM.
#include "gimp/core/interrupt.hpp"
#include "gimp/core/pair.hpp"
#include "gimp/solver/step.hpp"
#include "gimp/transfer/lane_loops.hpp"
#include "gimp/transfer/lane_loops3.hpp"

#include <cfloat>
#include <cmath>
#include <csignal>
#include <cstdio>

namespace gimp {

namespace {

/// The plane particles' test of k0 .. k1-1, both axes at once (the lanes of four first, where
/// they run).
PetscInt firstBadPlane(const RunState<2> &s, const ParticleView<2> &p, PetscInt k0, PetscInt k1,
                       double margin, PetscInt64 &leaving) {
  using simd::Pair;
  const double *d = s.sc.domain.data(), h0 = s.grid.h0();
  double box[4] = {-INFINITY, -INFINITY, INFINITY, INFINITY};
  if (s.size > 1) s.grid.ownedBox(s.rank, box);
  const Pair lo = {d[0] - margin, d[1] - margin}, hi = {d[2] + margin, d[3] + margin},
             own0 = {box[0], box[1]}, own1 = {box[2], box[3]}, hmax = simd::splat(h0),
             zero = {0, 0};
  PetscInt bad = -1;
  if (s.lanes) {
    const double lo2[2] = {lo[0], lo[1]}, hi2[2] = {hi[0], hi[1]};
    const PetscInt first = k0;
    k0 += transfer::laneLoops::checkParticles(k1 - k0, p.x + 2 * k0, p.l + 2 * k0,
                                              p.s + kStress<2> * k0, p.V + k0, lo2, hi2, h0, box,
                                              box + 2, s.size > 1, bad, leaving);
    if (bad >= 0) bad += first;
  }
  for (PetscInt k = k0; k < k1; ++k) {
    const Pair X = simd::load(p.x + 2 * k), l = simd::load(p.l + 2 * k);
    if (s.size > 1) leaving += !(simd::bothLe(own0, X) && simd::bothLt(X, own1));
    if (bad >= 0) continue;
    const double *sk = p.s + kStress<2> * k;
    const double sum = sk[0] + sk[1] + sk[2];
    // NaN fails every comparison: the test is written so that it lands in the bad branch.
    const bool ok = std::isfinite(X[0] + X[1] + sum) && p.V[k] > 0 && simd::bothLe(lo, X - l) &&
                    simd::bothLe(X + l, hi) && simd::bothLt(zero, l) && simd::bothLe(l, hmax);
    if (!ok) bad = k;
  }
  return bad;
}

/// The solid particles' test of k0 .. k1-1.
PetscInt firstBadSolid(const RunState<3> &s, const ParticleView<3> &p, PetscInt k0, PetscInt k1,
                       double margin, PetscInt64 &leaving) {
  const double *d = s.sc.domain.data(), h0 = s.grid.h0();
  double box[6] = {-INFINITY, -INFINITY, -INFINITY, INFINITY, INFINITY, INFINITY};
  if (s.size > 1) s.grid.ownedBox(s.rank, box);
  PetscInt bad = -1;
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = d[a] - margin;
    hi[a] = d[3 + a] + margin;
  }
  if (s.lanes) { // (the lanes test every particle, x, y and z at once)
    const PetscInt first = k0;
    k0 += transfer::laneLoops::checkParticles(k1 - k0, p.x + 3 * k0, p.l + 3 * k0, p.v + 3 * k0,
                                              p.s + kStress<3> * k0, p.V + k0, lo, hi, h0, box,
                                              box + 3, bad, leaving);
    if (bad >= 0) bad += first;
  }
  // Without branches: z is 0 when the stress entries and each x_a + v_a are finite, NaN
  // otherwise (a non-finite value times 0 is NaN); NaN fails every comparison, so a particle
  // with one lands in the bad branch.
  for (PetscInt k = k0; k < k1; ++k) {
    const double *x = p.x + 3 * k, *l = p.l + 3 * k, *v = p.v + 3 * k, *sk = p.s + kStress<3> * k;
    double z = 0.0;
    for (int e = 0; e < kStress<3>; ++e)
      z += sk[e] * 0.0;
    bool mine = true, ok = p.V[k] > 0 && p.V[k] <= DBL_MAX;
    for (int a = 0; a < 3; ++a) {
      z += (x[a] + v[a]) * 0.0;
      mine = mine & (x[a] >= box[a]) & (x[a] < box[3 + a]);
      ok = ok & (x[a] - l[a] >= lo[a]) & (x[a] + l[a] <= hi[a]) & (l[a] > 0) & (l[a] <= h0);
    }
    ok = ok & (z == 0.0);
    leaving += !mine;
    if (!ok && bad < 0) bad = k;
  }
  return bad;
}

/// "(x, y[, z])" with 9 digits.
template <int D> std::string point(const double *x) {
  std::string r = "(";
  for (int a = 0; a < D; ++a) {
    char b[40];
    std::snprintf(b, sizeof(b), "%s%.9g", a ? ", " : "", x[a]);
    r += b;
  }
  return r + ")";
}

} // namespace

template <int D>
PetscInt Step<D>::firstBadParticle(const ParticleView<D> &p, PetscInt k0, PetscInt k1,
                                   PetscInt64 &leaving) const {
  // A body flush with the domain's edge (on a symmetry roller, say) moves its edge particles'
  // domains past it by round-off (1e-18 m): a margin of 1e-8 h0 tells that from leaving.
  const double margin = 1e-8 * s_.grid.h0();
  if constexpr (D == 2)
    return firstBadPlane(s_, p, k0, k1, margin, leaving);
  else
    return firstBadSolid(s_, p, k0, k1, margin, leaving);
}

template <int D> std::string Step<D>::grewOf(const ParticleView<D> &p, PetscInt k) const {
  // Far outside what a solid does: a particle faster than kSpeed c_p of its material, or whose
  // volume changed by more than a factor kVolume (docs/validation.md, *Unstable runs*).
  constexpr double kSpeed = 2, kVolume = 100;
  const double cp = s_.sc.materialOf(p.id[k]).waveSpeed(), J = p.V[k] / p.V0[k];
  double v2 = 0;
  for (int a = 0; a < D; ++a)
    v2 += p.v[D * k + a] * p.v[D * k + a];
  const double speed = std::sqrt(v2);
  if (speed > kSpeed * cp)
    return "its speed " + formatNumber(speed) + " m/s is " + formatNumber(speed / cp) +
           " times c_p = " + formatNumber(cp) + " m/s";
  if (J > kVolume || J < 1 / kVolume)
    return "its volume ratio V / V0 = " + formatNumber(J) + " is outside [1/" +
           formatNumber(kVolume) + ", " + formatNumber(kVolume) + "]";
  return "";
}

template <int D>
std::string Step<D>::failureOf(const ParticleView<D> &p, PetscInt k, PetscInt step,
                               double t) const {
  const double *x = p.x + D * k, *l = p.l + D * k, *d = s_.sc.domain.data();
  const double margin = 1e-8 * s_.grid.h0();
  bool finite = stressAt<D>(p.s, k).allFinite(), inside = true, in = true;
  for (int a = 0; a < D; ++a) {
    finite = finite && std::isfinite(x[a]);
    inside = inside && x[a] - l[a] >= d[a] - margin && x[a] + l[a] <= d[D + a] + margin;
    in = in && x[a] >= d[a] && x[a] <= d[D + a];
  }
  const std::string unstable =
      ": the run went unstable (reduce -ts_dt: " + s_.stepAgainstCfl() + ", or the loads)";
  const std::string grew = finite && p.V[k] > 0 ? grewOf(p, k) : "";
  std::string why;
  if (!finite)
    why = "its position or stress is not finite" + unstable;
  else if (!(p.V[k] > 0))
    why = "its volume " + formatNumber(p.V[k]) + (D == 2 ? " m^2" : " m^3") +
          " is not positive: the particle is inverted (det F <= 0)" + unstable;
  else if (!grew.empty())
    why = grew + unstable + (inside ? "; its half-size left (0, h0]" : "; it left the grid domain");
  else if (!inside)
    why = "it left the grid domain (enlarge -gimp_domain or -gimp_pad: a body on the domain's "
          "edge deforms past it)";
  else
    why = "its half-size " + point<D>(l) +
          " is not in (0, h0]: the particle is inverted or stretched beyond one level-0 cell";
  // The level whose leaf cell holds the particle (none when it is not finite or outside).
  const std::string level = in && finite ? std::to_string(s_.grid.leafLevelAt(x)) : "none";
  char head[128];
  std::snprintf(head, sizeof(head), "step %lld t %.9g s: particle %lld at ",
                static_cast<long long>(step), t, static_cast<long long>(p.id[k]));
  return head + point<D>(x) + " on level " + level + ": " + why;
}

template <int D>
PetscErrorCode Step<D>::checks(const ParticleView<D> &p, PetscInt step, double t,
                               const CheckTally *tested) {
  RunState<D> &s = s_;
  RunStatus &st = s.status;
  CheckTally all;
  if (tested)
    all = *tested;
  else
    all.bad = firstBadParticle(p, 0, p.n, all.leaving);
  const PetscInt bad = all.bad;
  const PetscInt64 leaving = all.leaving;
  std::string line;
  if (bad >= 0) {
    line = failureOf(p, bad, step, t);
  } else if (!st.localFailure.empty()) {
    char head[64];
    std::snprintf(head, sizeof(head), "step %lld t %.9g s: ", static_cast<long long>(step), t);
    line = head + st.localFailure;
  }
  st.localFailure.clear();
  // One reduction for all: ranks that failed, got SIGINT, got SIGTERM, and the particles that
  // leave their rank (the step's only collective call besides the scatters).
  const int sig = interruptSignal();
  const PetscInt64 mine[4] = {line.empty() ? 0 : 1, sig == SIGINT ? 1 : 0, sig == SIGTERM ? 1 : 0,
                              leaving};
  PetscInt64 any[4] = {0, 0, 0, 0};
  PetscCallMPI(MPI_Allreduce(mine, any, 4, MPI_INT64_T, MPI_SUM, s.comm));
  st.interrupt = any[2] ? SIGTERM : any[1] ? SIGINT : 0;
  st.leaving = any[3];
  if (any[0] == 0) return PETSC_SUCCESS;
  st.failed = true;
  // The lowest failing rank's line (collective, so only when some rank failed): printed once
  // and kept for summary.json.
  PetscMPIInt first = s.size, me = line.empty() ? s.size : s.rank;
  PetscCallMPI(MPI_Allreduce(&me, &first, 1, MPI_INT, MPI_MIN, s.comm));
  int len = static_cast<int>(line.size());
  PetscCallMPI(MPI_Bcast(&len, 1, MPI_INT, first, s.comm));
  line.resize(static_cast<size_t>(len));
  PetscCallMPI(MPI_Bcast(line.data(), len, MPI_CHAR, first, s.comm));
  st.failure = line;
  PetscCall(PetscFPrintf(s.comm, PETSC_STDERR, "gimp: error: %s\n", line.c_str()));
  return PETSC_SUCCESS;
}

template PetscErrorCode Step<2>::checks(const ParticleView<2> &, PetscInt, double,
                                        const CheckTally *);
template PetscErrorCode Step<3>::checks(const ParticleView<3> &, PetscInt, double,
                                        const CheckTally *);
template PetscInt Step<2>::firstBadParticle(const ParticleView<2> &, PetscInt, PetscInt,
                                            PetscInt64 &) const;
template PetscInt Step<3>::firstBadParticle(const ParticleView<3> &, PetscInt, PetscInt,
                                            PetscInt64 &) const;

} // namespace gimp
