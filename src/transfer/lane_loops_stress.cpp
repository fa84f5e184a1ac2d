// Lanes of four 2D block particles (AVX2), the loops on the stress side of the step: the internal
// force, the velocity gradient, the linear-elastic stress update and the particle checks (APIC's
// transfers are in lane_loops.cpp, the pieces both share in lane_runs.hpp; see
// transfer/lane_loops.hpp). Every lane expression below is the scalar one in the same order,
// contracted into fused multiply-adds where the compiler finds them (the scalar results to
// round-off).
#include "gimp/transfer/lane_loops.hpp"

#include "gimp/physics/deformation.hpp"
#include "gimp/physics/material.hpp"
#include "gimp/transfer/internal_force.hpp"
#include "gimp/transfer/transfer.hpp"

#include <cmath>

#include "gimp/core/lanes.hpp"
#include "lane_runs.hpp"

namespace gimp::transfer::laneLoops {

#if GIMP_HAVE_LANES

GIMP_LANES void internalForce(const Stencils<2> &st, PetscInt n, const double *V,
                              const double *stress, double *f) {
  const auto lane = [&](PetscInt k, std::uint8_t group) GIMP_LANES_LAMBDA {
    prefetch::fields(k, n, Field<kStress<2>>{stress}, Field<1>{V});
    Run R;
    loadRun<true>(st, k, group, R);
    V4 S[4];
    loadStress(stress, k, S);
    const V4 nV = _mm256_xor_pd(_mm256_loadu_pd(V + k), splat(-0.0));
    const V4 A00 = nV * S[0], A01 = nV * S[1], A10 = nV * S[2], A11 = nV * S[3];
    // blocks::internalForce: f_ij += g_i (A0 w_j) + w_i (A1 g_j), A0 = (A00, A10), A1 = (A01, A11)
    NodeValues N;
    for (int j = 0; j < 3; ++j) {
      const V4 ax = A00 * R.wy[j], ay = A10 * R.wy[j], cx = A01 * R.gy[j], cy = A11 * R.gy[j];
      for (int i = 0; i < 3; ++i) {
        N.X[j][i] = R.gx[i] * ax + R.wx[i] * cx;
        N.Y[j][i] = R.gx[i] * ay + R.wx[i] * cy;
      }
    }
    if (R.split == 0) // a run of one block: each node's four at once
      addSummed<false>(R, N, f, nullptr);
    else
      addToNodes<false>(R, N, f, nullptr);
  };
  forGroups(st, 0, n, lane,
            [&](PetscInt k) { transfer::internalForce<2>(st, k, k + 1, V, stress, f); });
}

GIMP_LANES void velocityGradients(const Stencils<2> &st, PetscInt k0, PetscInt k1, const double *vg,
                                  double *L) {
  const auto lane = [&](PetscInt k, std::uint8_t group) GIMP_LANES_LAMBDA {
    Run R;
    loadRun<true>(st, k, group, R);
    byBlock(R, [&](auto one) GIMP_LANES_LAMBDA {
      constexpr bool One = decltype(one)::value;
      // blocks::gradient: L0 = sum_j w_j sum_i g_i v_ij, L1 = sum_j g_j sum_i w_i v_ij
      V4 L0x = splat(0), L0y = splat(0), L1x = splat(0), L1y = splat(0);
      for (int j = 0; j < 3; ++j) {
        const double *r[4] = {vg + R.row[j][0], vg + R.row[j][1], vg + R.row[j][2],
                              vg + R.row[j][3]};
        V4 px, py, sx, sy;
        for (int i = 0; i < 3; ++i) {
          V4 gx, gy;
          gatherPairs<One>(r, 2 * i, gx, gy);
          if (i == 0) {
            px = R.gx[0] * gx;
            py = R.gx[0] * gy;
            sx = R.wx[0] * gx;
            sy = R.wx[0] * gy;
          } else {
            px = px + R.gx[i] * gx;
            py = py + R.gx[i] * gy;
            sx = sx + R.wx[i] * gx;
            sy = sy + R.wx[i] * gy;
          }
        }
        L0x = L0x + R.wy[j] * px;
        L0y = L0y + R.wy[j] * py;
        L1x = L1x + R.gy[j] * sx;
        L1y = L1y + R.gy[j] * sy;
      }
      const V4 Lk[4] = {L0x, L1x, L0y, L1y};
      storeTensors(L, k - k0, Lk);
    });
  };
  forGroups(st, k0, k1, lane,
            [&](PetscInt k) { tensorAt<2>(L, k - k0) = velocityGradientAt<2>(st, k, vg); });
}

GIMP_LANES void updateDeformation(const Scene<2> &sc, ParticleView<2> &p, const double *L,
                                  double dt, PetscInt k0, PetscInt k1) {
  const bool stretch = sc.tracking == Tracking::Stretch;
  const bool lanes = stretch || sc.tracking == Tracking::None;
  const V4 DT = splat(dt), HALF = splat(0.5), ONE = splat(1.0), ZERO = splat(0.0), TWO = splat(2.0),
           MTWO = splat(-2.0);
  PetscInt k = k0;
  while (lanes && k + 4 <= k1) {
    const Material &mat = sc.materialOf(p.id[k]);
    if (mat.model != MaterialModel::Linear || &sc.materialOf(p.id[k + 1]) != &mat ||
        &sc.materialOf(p.id[k + 2]) != &mat || &sc.materialOf(p.id[k + 3]) != &mat) {
      physics::updateDeformation(sc, p, L + 4 * (k - k0), dt, k, k + 1);
      ++k;
      continue;
    }
    prefetch::fields(k, p.n, Field<4>{p.F}, Field<kStress<2>>{p.s}, Field<1>{p.V}, Field<1>{p.V0});
    if (mat.planeStrain) prefetch::fields(k, p.n, Field<1>{p.szz});
    if (stretch) prefetch::fields(k, p.n, Field<2>{p.l0}, Field<2>{p.l});
    V4 Lk[4], F[4], S[4];
    loadTensors(L, k - k0, Lk);
    loadTensors(p.F, k, F);
    // physics::updateDeformation: F += dt L F, entry (i, j) dt (L_i0 F_0j + L_i1 F_1j)
    const V4 Fn[4] = {
        F[0] + DT * (Lk[0] * F[0] + Lk[1] * F[2]), F[1] + DT * (Lk[0] * F[1] + Lk[1] * F[3]),
        F[2] + DT * (Lk[2] * F[0] + Lk[3] * F[2]), F[3] + DT * (Lk[2] * F[1] + Lk[3] * F[3])};
    storeTensors(p.F, k, Fn);
    _mm256_storeu_pd(p.V + k, (Fn[0] * Fn[3] - Fn[1] * Fn[2]) * _mm256_loadu_pd(p.V0 + k));
    // material::jaumannUpdate: D = (L + L^T) / 2, w = W_xy, the spin in closed form
    const V4 D00 = HALF * (Lk[0] + Lk[0]), D01 = HALF * (Lk[1] + Lk[2]),
             D10 = HALF * (Lk[2] + Lk[1]), D11 = HALF * (Lk[3] + Lk[3]);
    const V4 w = HALF * (Lk[1] - Lk[2]);
    const V4 tr = D00 + D11;
    loadStress(p.s, k, S);
    const V4 a = TWO * w * S[1], b = w * (S[3] - S[0]), c = MTWO * w * S[1];
    const V4 lt = splat(mat.lambdaStar) * tr, mu2 = splat(2.0 * mat.mu);
    const V4 Sn[4] = {
        S[0] + DT * (lt * ONE + mu2 * D00 + a), S[1] + DT * (lt * ZERO + mu2 * D01 + b),
        S[2] + DT * (lt * ZERO + mu2 * D10 + b), S[3] + DT * (lt * ONE + mu2 * D11 + c)};
    storeStress(p.s, k, Sn);
    if (mat.planeStrain)
      _mm256_storeu_pd(p.szz + k, _mm256_loadu_pd(p.szz + k) + DT * splat(mat.lambda) * tr);
    if (stretch) { // tracking::updateDomain: l_a = |F e_a| l0_a
      V4 L0x, L0y;
      loadVectors(p.l0, k, L0x, L0y);
      storeVectors(p.l, k, _mm256_sqrt_pd(Fn[0] * Fn[0] + Fn[2] * Fn[2]) * L0x,
                   _mm256_sqrt_pd(Fn[1] * Fn[1] + Fn[3] * Fn[3]) * L0y);
    }
    k += 4;
  }
  if (k < k1) physics::updateDeformation(sc, p, L + 4 * (k - k0), dt, k, k1);
}

GIMP_LANES PetscInt checkParticles(PetscInt n, const double *x, const double *l, const double *s,
                                   const double *V, const double *lo, const double *hi, double hmax,
                                   const double *own0, const double *own1, bool count,
                                   PetscInt &bad, PetscInt64 &leaving) {
  const PetscInt n4 = n / 4 * 4;
  const V4 lox = splat(lo[0]), loy = splat(lo[1]), hix = splat(hi[0]), hiy = splat(hi[1]),
           hm = splat(hmax), zero = splat(0.0), inf = splat(INFINITY), sign = splat(-0.0),
           o0x = splat(own0[0]), o0y = splat(own0[1]), o1x = splat(own1[0]), o1y = splat(own1[1]);
  bad = -1;
  for (PetscInt k = 0; k < n4; k += 4) {
    prefetch::fields(k, n, Field<2>{x}, Field<2>{l}, Field<kStress<2>>{s}, Field<1>{V});
    V4 X, Y, LX, LY, S[4];
    loadVectors(x, k, X, Y);
    if (count) { // !(own0 <= x && x < own1), both axes
      const V4 in = _mm256_and_pd(
          _mm256_and_pd(_mm256_cmp_pd(o0x, X, _CMP_LE_OQ), _mm256_cmp_pd(o0y, Y, _CMP_LE_OQ)),
          _mm256_and_pd(_mm256_cmp_pd(X, o1x, _CMP_LT_OQ), _mm256_cmp_pd(Y, o1y, _CMP_LT_OQ)));
      leaving += 4 - __builtin_popcount(static_cast<unsigned>(_mm256_movemask_pd(in)));
    }
    if (bad >= 0) continue;
    loadVectors(l, k, LX, LY);
    loadStress(s, k, S);
    const V4 sum = X + Y + (S[0] + S[3] + S[1]);
    V4 ok = _mm256_cmp_pd(_mm256_andnot_pd(sign, sum), inf, _CMP_LT_OQ); // finite
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(_mm256_loadu_pd(V + k), zero, _CMP_GT_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(lox, X - LX, _CMP_LE_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(loy, Y - LY, _CMP_LE_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(X + LX, hix, _CMP_LE_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(Y + LY, hiy, _CMP_LE_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(zero, LX, _CMP_LT_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(zero, LY, _CMP_LT_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(LX, hm, _CMP_LE_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(LY, hm, _CMP_LE_OQ));
    const unsigned fails = ~static_cast<unsigned>(_mm256_movemask_pd(ok)) & 15u;
    if (fails) bad = k + __builtin_ctz(fails);
  }
  return n4;
}

#else // no lanes on this architecture: the scalar loops

void internalForce(const Stencils<2> &st, PetscInt n, const double *V, const double *stress,
                   double *f) {
  transfer::internalForce<2>(st, 0, n, V, stress, f);
}
void velocityGradients(const Stencils<2> &st, PetscInt k0, PetscInt k1, const double *vg,
                       double *L) {
  for (PetscInt k = k0; k < k1; ++k)
    tensorAt<2>(L, k - k0) = velocityGradientAt<2>(st, k, vg);
}
void updateDeformation(const Scene<2> &sc, ParticleView<2> &p, const double *L, double dt,
                       PetscInt k0, PetscInt k1) {
  physics::updateDeformation(sc, p, L, dt, k0, k1);
}
PetscInt checkParticles(PetscInt, const double *, const double *, const double *, const double *,
                        const double *, const double *, double, const double *, const double *,
                        bool, PetscInt &bad, PetscInt64 &) {
  bad = -1;
  return 0;
}

#endif

} // namespace gimp::transfer::laneLoops
