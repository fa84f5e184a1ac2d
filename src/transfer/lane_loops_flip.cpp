// Lanes of four 2D block particles (AVX2) for the FLIP/PIC transfers: see transfer/lane_loops.hpp.
// Unlike the other lane loop files this one is built without contraction (the project's default,
// CMakeLists.txt): every lane expression is the scalar one of transfer/block_kernels.hpp in its
// order and with its roundings, so these loops give the scalar loops' results bit for bit.
//
// This file: P2G of mass and momentum, G2P with the re-projection (MUSL) or without (USL, USF),
// and the G2P of a rate class of a per-level step.
#include "gimp/transfer/lane_loops.hpp"

#include "gimp/transfer/transfer.hpp"

#include "gimp/core/lanes.hpp"
#include "lane_runs.hpp"

namespace gimp::transfer::laneLoops {

#if GIMP_HAVE_LANES

namespace {

/// BlockLocals::scatter for a run: node (i, j) gets w_i (w_j p) and, with mass, w_i (w_j m).
GIMP_LANES_INLINE void momentumScatter(const Run &R, V4 mp, V4 PX, V4 PY, double *mom,
                                       double *mass) {
  NodeValues N;
  for (int j = 0; j < 3; ++j) {
    const V4 ax = R.wy[j] * PX, ay = R.wy[j] * PY, am = R.wy[j] * mp;
    for (int i = 0; i < 3; ++i) {
      N.X[j][i] = R.wx[i] * ax;
      N.Y[j][i] = R.wx[i] * ay;
      N.M[j][i] = R.wx[i] * am;
    }
  }
  if (mass)
    addToNodes<true>(R, N, mom, mass);
  else
    addToNodes<false>(R, N, mom, nullptr);
}

/// The FLIP/PIC G2P of a run (blocks::fromGrid, then gridToParticles' update): v <- flip (v + dt
/// a_p) + (1 - flip) v_p, x += dt v_p; returns the new velocities. One: the run is one block
/// (byBlock: its nodes read by one load each, the same values).
template <bool One>
GIMP_LANES_INLINE void flipUpdate(const Run &R, PetscInt k, const double *vg, const double *ag,
                                  double dt, double flip, double *v, double *x, V4 &VX, V4 &VY) {
  V4 vx, vy, ax, ay, X, Y;
  interpolateRun<One>(R, vg, vx, vy);
  interpolateRun<One>(R, ag, ax, ay);
  loadVectors(v, k, VX, VY);
  const V4 f = splat(flip), g = splat(1.0 - flip), dtv = splat(dt);
  VX = f * (VX + dtv * ax) + g * vx;
  VY = f * (VY + dtv * ay) + g * vy;
  storeVectors(v, k, VX, VY);
  loadVectors(x, k, X, Y);
  storeVectors(x, k, X + dtv * vx, Y + dtv * vy);
}

/// FLIP/PIC G2P of every particle (gridToParticles<2>) and, with Projected, the re-projection of
/// the new momenta into mom (gridToParticlesProjected<2>).
template <bool Projected>
GIMP_LANES_INLINE void flipG2P(const Stencils<2> &st, PetscInt n, const double *vg,
                               const double *ag, double dt, double flip, const double *m, double *v,
                               double *x, double *mom) {
  const auto lane = [&](PetscInt k, std::uint8_t group) GIMP_LANES_LAMBDA {
    if constexpr (Projected)
      prefetch::fields(k, n, Field<2>{v}, Field<2>{x}, Field<1>{m});
    else
      prefetch::fields(k, n, Field<2>{v}, Field<2>{x});
    Run R;
    loadRun<false>(st, k, group, R);
    V4 VX, VY;
    byBlock(R, [&](auto one) GIMP_LANES_LAMBDA {
      flipUpdate<decltype(one)::value>(R, k, vg, ag, dt, flip, v, x, VX, VY);
    });
    if constexpr (Projected) {
      const V4 mp = _mm256_loadu_pd(m + k);
      momentumScatter(R, mp, mp * VX, mp * VY, mom, nullptr);
    }
  };
  forGroups(st, 0, n, lane, [&](PetscInt k) {
    if constexpr (Projected)
      particleFromGridProjected<2>(st, k, vg, ag, dt, flip, m, v, x, mom);
    else
      particleFromGridFlip<2>(st, k, vg, ag, dt, flip, v, x);
  });
}

} // namespace

GIMP_LANES void particlesToGrid(const Stencils<2> &st, PetscInt n, const double *m, const double *v,
                                double *mom, double *mass) {
  const auto lane = [&](PetscInt k, std::uint8_t group) GIMP_LANES_LAMBDA {
    prefetch::fields(k, n, Field<2>{v}, Field<1>{m});
    Run R;
    loadRun<false>(st, k, group, R);
    V4 VX, VY;
    loadVectors(v, k, VX, VY);
    const V4 mp = _mm256_loadu_pd(m + k);
    momentumScatter(R, mp, mp * VX, mp * VY, mom, mass);
  };
  forGroups(st, 0, n, lane,
            [&](PetscInt k) { particleToGrid<2>(st, k, m[k], v + 2 * k, mom, mass); });
}

GIMP_LANES void gridToParticles(const Stencils<2> &st, PetscInt n, const double *vg,
                                const double *ag, double dt, double flip, double *v, double *x) {
  flipG2P<false>(st, n, vg, ag, dt, flip, nullptr, v, x, nullptr);
}

GIMP_LANES void gridToParticlesProjected(const Stencils<2> &st, PetscInt n, const double *vg,
                                         const double *ag, double dt, double flip, const double *m,
                                         double *v, double *x, double *mom) {
  flipG2P<true>(st, n, vg, ag, dt, flip, m, v, x, mom);
}

GIMP_LANES void gridToParticlesRated(const Stencils<2> &st, PetscInt n, const double *ug,
                                     const double *wg, double dt, double flip, const double *m,
                                     double *v, double *x, double *mom) {
  const auto lane = [&](PetscInt k, std::uint8_t group) GIMP_LANES_LAMBDA {
    prefetch::fields(k, n, Field<2>{v}, Field<2>{x}, Field<1>{m});
    Run R;
    loadRun<false>(st, k, group, R);
    V4 ux, uy, wx, wy, VX, VY, X, Y;
    byBlock(R, [&](auto one) GIMP_LANES_LAMBDA {
      interpolateRun<decltype(one)::value>(R, ug, ux, uy);
      interpolateRun<decltype(one)::value>(R, wg, wx, wy);
    });
    loadVectors(v, k, VX, VY);
    const V4 f = splat(flip), dtv = splat(dt);
    VX = f * VX + ux;
    VY = f * VY + uy;
    storeVectors(v, k, VX, VY);
    loadVectors(x, k, X, Y);
    storeVectors(x, k, X + dtv * wx, Y + dtv * wy);
    if (mom) {
      const V4 mp = _mm256_loadu_pd(m + k);
      momentumScatter(R, mp, mp * VX, mp * VY, mom, nullptr);
    }
  };
  forGroups(st, 0, n, lane,
            [&](PetscInt k) { particleFromGridRated<2>(st, k, ug, wg, dt, flip, m, v, x, mom); });
}

#else // no lanes on this architecture (laneLoops::available() is false): the scalar loops

void particlesToGrid(const Stencils<2> &st, PetscInt n, const double *m, const double *v,
                     double *mom, double *mass) {
  transfer::particlesToGrid<2>(st, n, m, v, mom, mass);
}
void gridToParticles(const Stencils<2> &st, PetscInt n, const double *vg, const double *ag,
                     double dt, double flip, double *v, double *x) {
  transfer::gridToParticles<2>(st, n, vg, ag, dt, flip, v, x);
}
void gridToParticlesProjected(const Stencils<2> &st, PetscInt n, const double *vg, const double *ag,
                              double dt, double flip, const double *m, double *v, double *x,
                              double *mom) {
  transfer::gridToParticlesProjected<2>(st, n, vg, ag, dt, flip, m, v, x, mom);
}
void gridToParticlesRated(const Stencils<2> &st, PetscInt n, const double *ug, const double *wg,
                          double dt, double flip, const double *m, double *v, double *x,
                          double *mom) {
  transfer::gridToParticlesRated<2>(st, n, ug, wg, dt, flip, m, v, x, mom);
}

#endif

} // namespace gimp::transfer::laneLoops
