// Lanes of four 2D block particles (AVX2): see transfer/lane_loops.hpp. Every lane expression below
// is the scalar one of transfer/block_kernels.hpp (named next to it) in the same order; this file
// is built with contraction for AVX2 with FMA (CMakeLists.txt), so products and sums fuse where
// the compiler finds them, and a run of one block sums each node's four contributions before it
// adds them (addSummed): the results are the scalar ones to round-off.
//
// This file: APIC's transfers, P2G and G2P (with the re-projection or without); the internal
// force, the velocity gradient, the stress update and the checks are in lane_loops_stress.cpp,
// the pieces both share in lane_runs.hpp.
#include "gimp/transfer/lane_loops.hpp"

#include "gimp/transfer/affine.hpp"

#include "gimp/core/lanes.hpp"
#include "lane_runs.hpp"

namespace gimp::transfer::laneLoops {

#if GIMP_HAVE_LANES

bool available() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}

namespace {

/// blocks::offsets for a run: the offsets dx, dy of its node lines from the centres (XP, YP).
/// One: the run is one block (byBlock), its node lines one load each.
template <bool One>
GIMP_LANES_INLINE void offsets(const Run &R, V4 XP, V4 YP, const double *xs, V4 *dx, V4 *dy) {
  if constexpr (One) {
    for (int i = 0; i < 3; ++i) {
      dx[i] = _mm256_broadcast_sd(xs + R.row[0][0] + 2 * i) - XP;
      dy[i] = _mm256_broadcast_sd(xs + R.row[i][0] + 1) - YP;
    }
    return;
  }
  for (int i = 0; i < 3; ++i) {
    const PetscInt o = 2 * i;
    dx[i] = _mm256_set_pd(xs[R.row[0][3] + o], xs[R.row[0][2] + o], xs[R.row[0][1] + o],
                          xs[R.row[0][0] + o]) -
            XP;
    dy[i] = _mm256_set_pd(xs[R.row[i][3] + 1], xs[R.row[i][2] + 1], xs[R.row[i][1] + 1],
                          xs[R.row[i][0] + 1]) -
            YP;
  }
}

/// blocks::offsetsAndInverseInertia (N = 3): the offsets dx, dy of the run's node lines from
/// the centres (XP, YP) and D^-1 (xx, xy, yx, yy), 0 where D is singular (invertInertia).
template <bool One>
GIMP_LANES_INLINE void offsetsAndInverseInertia(const Run &R, V4 XP, V4 YP, const double *xs,
                                                V4 *dx, V4 *dy, V4 *Di) {
  offsets<One>(R, XP, YP, xs, dx, dy);
  V4 S0x = splat(0), S1x = splat(0), S2x = splat(0), S0y = splat(0), S1y = splat(0), S2y = splat(0);
  for (int i = 0; i < 3; ++i) {
    const V4 tx = R.wx[i] * dx[i], ty = R.wy[i] * dy[i];
    S0x = S0x + R.wx[i];
    S0y = S0y + R.wy[i];
    S1x = S1x + tx;
    S1y = S1y + ty;
    S2x = S2x + tx * dx[i];
    S2y = S2y + ty * dy[i];
  }
  // invertInertia(a, b, b, d) with a = Sx2 Sy0, b = Sx1 Sy1, d = Sx0 Sy2
  const V4 a = S2x * S0y, b = S1x * S1y, d = S0x * S2y;
  const V4 det = a * d - b * b;
  const V4 half = splat(0.5) * (a + d);
  const V4 ok = _mm256_cmp_pd(det, splat(1e-12) * half * half, _CMP_GT_OQ);
  // (1 / det only where D is regular: no division by 0 in the other lanes, which -fp_trap would
  // stop on where the scalar code never divides)
  const V4 id = splat(1.0) / _mm256_blendv_pd(splat(1.0), det, ok);
  const V4 nb = _mm256_xor_pd(b, splat(-0.0));
  Di[0] = _mm256_and_pd(ok, d * id);
  Di[1] = _mm256_and_pd(ok, nb * id);
  Di[2] = _mm256_and_pd(ok, nb * id);
  Di[3] = _mm256_and_pd(ok, a * id);
}

/// product<2>(B, Di).
GIMP_LANES_INLINE void product(const V4 *B, const V4 *Di, V4 *C) {
  C[0] = B[0] * Di[0] + B[1] * Di[2];
  C[1] = B[0] * Di[1] + B[1] * Di[3];
  C[2] = B[2] * Di[0] + B[3] * Di[2];
  C[3] = B[2] * Di[1] + B[3] * Di[3];
}

/// blocks::affineScatter: node (i, j) gets m w_j [w_i (v + C e_y dy_j) + w_i dx_i C e_x] and, with
/// mass, m w_i w_j; a run of one block (One) adds each node's four at once (addSummed).
template <bool One>
GIMP_LANES_INLINE void affineScatter(const Run &R, V4 mp, V4 VX, V4 VY, const V4 *C, const V4 *dx,
                                     const V4 *dy, double *mom, double *mass) {
  NodeValues N;
  V4 wdx[3];
  for (int i = 0; i < 3; ++i)
    wdx[i] = R.wx[i] * dx[i];
  for (int j = 0; j < 3; ++j) {
    const V4 mw = mp * R.wy[j];
    const V4 rx = mw * (VX + C[1] * dy[j]), ry = mw * (VY + C[3] * dy[j]);
    const V4 tx = mw * C[0], ty = mw * C[2];
    for (int i = 0; i < 3; ++i) {
      N.X[j][i] = R.wx[i] * rx + wdx[i] * tx;
      N.Y[j][i] = R.wx[i] * ry + wdx[i] * ty;
      N.M[j][i] = R.wx[i] * mw;
    }
  }
  if constexpr (One) {
    if (mass)
      addSummed<true>(R, N, mom, mass);
    else
      addSummed<false>(R, N, mom, nullptr);
  } else {
    if (mass)
      addToNodes<true>(R, N, mom, mass);
    else
      addToNodes<false>(R, N, mom, nullptr);
  }
}

} // namespace

GIMP_LANES void particlesToGridAffineB(const Stencils<2> &st, PetscInt n, const double *m,
                                       const double *v, const double *B, const double *xc,
                                       const double *xs, double *mom, double *mass) {
  const auto lane = [&](PetscInt k, std::uint8_t group) GIMP_LANES_LAMBDA {
    prefetch::fields(k, n, Field<2>{xc}, Field<2>{v}, Field<4>{B}, Field<1>{m});
    Run R;
    loadRun<false>(st, k, group, R);
    byBlock(R, [&](auto one) GIMP_LANES_LAMBDA {
      constexpr bool One = decltype(one)::value;
      V4 XP, YP, VX, VY, Bk[4], Di[4], C[4], dx[3], dy[3];
      loadVectors(xc, k, XP, YP);
      loadVectors(v, k, VX, VY);
      loadTensors(B, k, Bk);
      offsetsAndInverseInertia<One>(R, XP, YP, xs, dx, dy, Di);
      product(Bk, Di, C);
      affineScatter<One>(R, _mm256_loadu_pd(m + k), VX, VY, C, dx, dy, mom, mass);
    });
  };
  forGroups(st, 0, n, lane, [&](PetscInt k) {
    particleToGridAffineB<2>(st, k, m[k], v + 2 * k, tensorAt<2>(B, k), xc + 2 * k, xs, mom, mass);
  });
}

namespace {

/// blocks::affineGather for a run: v_p = sum_j w_j t_j, B0 = sum_j w_j u_j, B1 = sum_j (w_j dy_j)
/// t_j with t_j = sum_i w_i v_ij, u_j = sum_i (w_i v_ij) dx_i; B_p = (B0x, B1x; B0y, B1y).
template <bool One>
GIMP_LANES_INLINE void affineGather(const Run &R, const double *vg, const V4 *dx, const V4 *dy,
                                    V4 &vx, V4 &vy, V4 *Bk) {
  V4 B0x = splat(0), B0y = splat(0), B1x = splat(0), B1y = splat(0);
  vx = splat(0);
  vy = splat(0);
  for (int j = 0; j < 3; ++j) {
    const double *r[4] = {vg + R.row[j][0], vg + R.row[j][1], vg + R.row[j][2], vg + R.row[j][3]};
    V4 tx, ty, ux, uy;
    for (int i = 0; i < 3; ++i) {
      V4 gx, gy;
      gatherPairs<One>(r, 2 * i, gx, gy);
      const V4 wvx = R.wx[i] * gx, wvy = R.wx[i] * gy;
      if (i == 0) {
        tx = wvx;
        ty = wvy;
        ux = wvx * dx[0];
        uy = wvy * dx[0];
      } else {
        tx = tx + wvx;
        ty = ty + wvy;
        ux = ux + wvx * dx[i];
        uy = uy + wvy * dx[i];
      }
    }
    const V4 wdy = R.wy[j] * dy[j];
    vx = vx + R.wy[j] * tx;
    vy = vy + R.wy[j] * ty;
    B0x = B0x + R.wy[j] * ux;
    B0y = B0y + R.wy[j] * uy;
    B1x = B1x + wdy * tx;
    B1y = B1y + wdy * ty;
  }
  Bk[0] = B0x;
  Bk[1] = B1x;
  Bk[2] = B0y;
  Bk[3] = B1y;
}

/// APIC G2P of every particle, the move by dt v_p (with wg, by dt sum_i S_ip wg_i: a rate class
/// of a per-level step, gridToParticlesAffineRated) and, with Project, the re-projection of the
/// new affine momenta into mom (x may be xc: every centre of a run is read before it moves).
template <bool Project>
GIMP_LANES_INLINE void
gridToParticlesAffineRuns(const Stencils<2> &st, PetscInt n, const double *vg, const double *wg,
                          const double *xc, const double *xs, double dt, const double *m, double *v,
                          double *B, double *x, double *mom) {
  const auto one = [&](PetscInt k) {
    double vp[2], wp[2] = {0, 0};
    Tensor<2> Bk;
    if constexpr (Project)
      particleFromAndToGridAffine<2>(st, k, m[k], vg, xc + 2 * k, xs, vp, Bk, mom);
    else
      particleFromGridAffine<2>(st, k, vg, xc + 2 * k, xs, vp, Bk);
    if (wg) interpolateAt<2>(st, k, wg, wp);
    tensorAt<2>(B, k) = Bk;
    for (int c = 0; c < 2; ++c) {
      v[2 * k + c] = vp[c];
      x[2 * k + c] += dt * (wg ? wp[c] : vp[c]);
    }
  };
  // With weights centred on the positions (x == xc) the centres read first are the positions
  // the run moves: neither fetched nor loaded twice.
  const bool centredOnX = x == xc;
  const auto lane = [&](PetscInt k, std::uint8_t group) GIMP_LANES_LAMBDA {
    if constexpr (Project)
      prefetch::fields(k, n, Field<2>{xc}, Field<1>{m}, Field<4>{B}, Field<2>{v});
    else
      prefetch::fields(k, n, Field<2>{xc}, Field<4>{B}, Field<2>{v});
    if (!centredOnX) prefetch::fields(k, n, Field<2>{x});
    Run R;
    loadRun<false>(st, k, group, R);
    byBlock(R, [&](auto one) GIMP_LANES_LAMBDA {
      constexpr bool One = decltype(one)::value;
      V4 XP, YP, dx[3], dy[3], vx, vy, Bk[4];
      loadVectors(xc, k, XP, YP);
      if constexpr (Project) {
        V4 Di[4], C[4];
        offsetsAndInverseInertia<One>(R, XP, YP, xs, dx, dy, Di);
        affineGather<One>(R, vg, dx, dy, vx, vy, Bk);
        product(Bk, Di, C);
        affineScatter<One>(R, _mm256_loadu_pd(m + k), vx, vy, C, dx, dy, mom, nullptr);
      } else {
        offsets<One>(R, XP, YP, xs, dx, dy);
        affineGather<One>(R, vg, dx, dy, vx, vy, Bk);
      }
      storeTensors(B, k, Bk);
      storeVectors(v, k, vx, vy);
      V4 X = XP, Y = YP, ux = vx, uy = vy;
      if (!centredOnX) loadVectors(x, k, X, Y);
      if (wg) interpolateRun<One>(R, wg, ux, uy);
      const V4 dtv = splat(dt);
      storeVectors(x, k, X + dtv * ux, Y + dtv * uy);
    });
  };
  forGroups(st, 0, n, lane, one);
}

} // namespace

GIMP_LANES void gridToParticlesAffineProjected(const Stencils<2> &st, PetscInt n, const double *vg,
                                               const double *xc, const double *xs, double dt,
                                               const double *m, double *v, double *B, double *x,
                                               double *mom) {
  gridToParticlesAffineRuns<true>(st, n, vg, nullptr, xc, xs, dt, m, v, B, x, mom);
}

GIMP_LANES void gridToParticlesAffine(const Stencils<2> &st, PetscInt n, const double *vg,
                                      const double *xc, const double *xs, double dt, double *v,
                                      double *B, double *x) {
  gridToParticlesAffineRuns<false>(st, n, vg, nullptr, xc, xs, dt, nullptr, v, B, x, nullptr);
}

GIMP_LANES void gridToParticlesAffineRated(const Stencils<2> &st, PetscInt n, const double *vg,
                                           const double *wg, const double *xs, double dt,
                                           const double *m, double *v, double *B, double *x,
                                           double *mom) {
  const double *w = wg == vg ? nullptr : wg; // (moving with v_p)
  if (mom)
    gridToParticlesAffineRuns<true>(st, n, vg, w, x, xs, dt, m, v, B, x, mom);
  else
    gridToParticlesAffineRuns<false>(st, n, vg, w, x, xs, dt, nullptr, v, B, x, nullptr);
}

#else // no lanes on this architecture: the scalar loops

bool available() {
  return false;
}

void particlesToGridAffineB(const Stencils<2> &st, PetscInt n, const double *m, const double *v,
                            const double *B, const double *xc, const double *xs, double *mom,
                            double *mass) {
  transfer::particlesToGridAffineB<2>(st, n, m, v, B, xc, xs, mom, mass);
}
void gridToParticlesAffineProjected(const Stencils<2> &st, PetscInt n, const double *vg,
                                    const double *xc, const double *xs, double dt, const double *m,
                                    double *v, double *B, double *x, double *mom) {
  transfer::gridToParticlesAffineProjected<2>(st, n, vg, xc, xs, dt, m, v, B, x, mom);
}
void gridToParticlesAffine(const Stencils<2> &st, PetscInt n, const double *vg, const double *xc,
                           const double *xs, double dt, double *v, double *B, double *x) {
  transfer::gridToParticlesAffine<2>(st, n, vg, xc, xs, dt, v, B, x);
}
void gridToParticlesAffineRated(const Stencils<2> &st, PetscInt n, const double *vg,
                                const double *wg, const double *xs, double dt, const double *m,
                                double *v, double *B, double *x, double *mom) {
  transfer::gridToParticlesAffineRated<2>(st, n, vg, wg, xs, dt, m, v, B, x, mom);
}

#endif

} // namespace gimp::transfer::laneLoops
