// The 3D step's internal force, velocity gradient (a node's three components in lanes) and stress
// update (four particles in lanes), AVX2: see transfer/lane_loops3.hpp and lane_loops3.cpp.
#include "gimp/transfer/lane_loops3.hpp"

#include <cfloat>

#include "gimp/physics/deformation.hpp"
#include "gimp/physics/material.hpp"
#include "gimp/transfer/internal_force.hpp"
#include "gimp/transfer/transfer.hpp"

#include "lane_runs3.hpp"

namespace gimp::transfer::laneLoops {

#if GIMP_HAVE_LANES

namespace {

/// Entry e of the four row-major 3 x 3 tensors at a (36 doubles) in lanes: c[e] = (a[e], a[9 +
/// e], a[18 + e], a[27 + e]).
/// (Entries 0-3 and 4-7 of the four tensors by two 4 x 4 transposes of contiguous loads.)
GIMP_LANES_INLINE void loadTensors4(const double *a, V4 *c) {
  for (int h = 0; h < 2; ++h)
    lanes::transpose(_mm256_loadu_pd(a + 4 * h), _mm256_loadu_pd(a + 9 + 4 * h),
                     _mm256_loadu_pd(a + 18 + 4 * h), _mm256_loadu_pd(a + 27 + 4 * h), c + 4 * h);
  c[8] = _mm256_set_pd(a[35], a[26], a[17], a[8]);
}
/// Voigt entry e of the four symmetric stresses at a (kStress<3> = 6 entries each, 24 doubles)
/// in lanes, and back: entries 0-3 by a 4 x 4 transpose, 4 and 5 as pairs.
GIMP_LANES_INLINE void loadStress4(const double *a, V4 *c) {
  lanes::transpose(_mm256_loadu_pd(a), _mm256_loadu_pd(a + 6), _mm256_loadu_pd(a + 12),
                   _mm256_loadu_pd(a + 18), c);
  const V4 u = _mm256_loadu2_m128d(a + 16, a + 4), w = _mm256_loadu2_m128d(a + 22, a + 10);
  c[4] = _mm256_unpacklo_pd(u, w);
  c[5] = _mm256_unpackhi_pd(u, w);
}
GIMP_LANES_INLINE void storeStress4(double *a, const V4 *c) {
  V4 r[4];
  lanes::transpose(c[0], c[1], c[2], c[3], r);
  for (int q = 0; q < 4; ++q)
    _mm256_storeu_pd(a + 6 * q, r[q]);
  _mm256_storeu2_m128d(a + 16, a + 4, _mm256_unpacklo_pd(c[4], c[5]));
  _mm256_storeu2_m128d(a + 22, a + 10, _mm256_unpackhi_pd(c[4], c[5]));
}
GIMP_LANES_INLINE void storeTensors4(double *a, const V4 *c) {
  V4 r[4];
  for (int h = 0; h < 2; ++h) {
    lanes::transpose(c[4 * h], c[4 * h + 1], c[4 * h + 2], c[4 * h + 3], r);
    for (int q = 0; q < 4; ++q)
      _mm256_storeu_pd(a + 9 * q + 4 * h, r[q]);
  }
  alignas(32) double t[4];
  _mm256_store_pd(t, c[8]);
  for (int q = 0; q < 4; ++q)
    a[9 * q + 8] = t[q];
}
/// Component a of the four 3-vectors at p in lanes, and back.
GIMP_LANES_INLINE V4 loadComponent4(const double *p, int a) {
  return _mm256_set_pd(p[9 + a], p[6 + a], p[3 + a], p[a]);
}
GIMP_LANES_INLINE void storeComponent4(double *p, int a, V4 v) {
  alignas(32) double t[4];
  _mm256_store_pd(t, v);
  for (int q = 0; q < 4; ++q)
    p[3 * q + a] = t[q];
}

} // namespace

GIMP_LANES void internalForce(const Stencils<3> &st, PetscInt n, const double *V,
                              const double *stress, double *f) {
  for (PetscInt k = 0; k < n; ++k) {
    prefetchRecord(st, k, n);
    if (k % 4 == 0)
      prefetch::fields(k, n, prefetch::Field<kStress<3>>{stress}, prefetch::Field<1>{V});
    const Tensor<3> A = -V[k] * stressAt<3>(stress, k);
    const V4 Ax = column(A, 0), Ay = column(A, 1), Az = column(A, 2);
    if (!st.isBlock(k)) {
      forRows(st, k, [&](PetscInt nd, double, const Vector<3> &gr) GIMP_LANES_LAMBDA {
        const V4 fc = Ax * splat(gr[0]) + Ay * splat(gr[1]) + Az * splat(gr[2]);
        store3(f + 3 * nd, load3(f + 3 * nd) + fc);
      });
      continue;
    }
    // A block's node (i, j, q) has the gradient (g_i w_j w_q, w_i g_j w_q, w_i w_j g_q): its
    // force is g_i P + w_i Q with P = w_j w_q A_x and Q = g_j w_q A_y + w_j g_q A_z per row.
    const Block<3> b = st.block(k);
    int nn[3];
    reached(b, nn);
    for (int q = 0; q < nn[2]; ++q)
      for (int j = 0; j < nn[1]; ++j) {
        const V4 P = splat(b.w[1][j] * b.w[2][q]) * Ax,
                 Q = splat(b.g[1][j] * b.w[2][q]) * Ay + splat(b.w[1][j] * b.g[2][q]) * Az;
        double *r = f + 3 * (b.base + j * b.stride[0] + q * b.stride[1]);
        for (int i = 0; i < nn[0]; ++i)
          store3(r + 3 * i, load3(r + 3 * i) + splat(b.g[0][i]) * P + splat(b.w[0][i]) * Q);
      }
  }
}

GIMP_LANES void velocityGradients(const Stencils<3> &st, PetscInt k0, PetscInt k1, const double *vg,
                                  double *L) {
  for (PetscInt k = k0; k < k1; ++k) {
    prefetchRecord(st, k, k1);
    auto Lk = tensorAt<3>(L, k - k0);
    if (!st.isBlock(k)) { // velocityGradientAt<3> of a particle that keeps rows
      V4 Lc[3] = {splat(0.0), splat(0.0), splat(0.0)};
      forRows(st, k, [&](PetscInt nd, double, const Vector<3> &gr) GIMP_LANES_LAMBDA {
        const V4 vn = load3(vg + 3 * nd);
        for (int a = 0; a < 3; ++a)
          Lc[a] = Lc[a] + vn * splat(gr[a]);
      });
      setColumns(Lc, Lk);
      continue;
    }
    // velocityGradientAt<3>, block branch: rows along x (sum_i g_i v and sum_i w_i v), then the
    // (y, z) factors; the columns of L in lanes.
    const Block<3> b = st.block(k);
    V4 Lc[3] = {splat(0.0), splat(0.0), splat(0.0)};
    for (int q = 0; q < 3; ++q)
      for (int j = 0; j < 3; ++j) {
        const double *r = vg + 3 * (b.base + j * b.stride[0] + q * b.stride[1]);
        V4 PG = splat(0.0), QW = splat(0.0);
        for (int i = 0; i < 3; ++i) {
          const V4 vn = load3(r + 3 * i);
          PG = PG + splat(b.g[0][i]) * vn;
          QW = QW + splat(b.w[0][i]) * vn;
        }
        const double wyz = b.w[1][j] * b.w[2][q], gy = b.g[1][j] * b.w[2][q],
                     gz = b.w[1][j] * b.g[2][q];
        Lc[0] = Lc[0] + splat(wyz) * PG;
        Lc[1] = Lc[1] + splat(gy) * QW;
        Lc[2] = Lc[2] + splat(gz) * QW;
      }
    setColumns(Lc, Lk);
  }
}

GIMP_LANES void updateDeformation(const Scene<3> &sc, ParticleView<3> &p, const double *L,
                                  double dt, PetscInt k0, PetscInt k1) {
  const bool stretch = sc.tracking == Tracking::Stretch;
  const bool lanes = stretch || sc.tracking == Tracking::None;
  const V4 DT = splat(dt), HALF = splat(0.5), TWO = splat(2.0);
  PetscInt k = k0;
  while (lanes && k + 4 <= k1) {
    const Material &mat = sc.materialOf(p.id[k]);
    if (mat.model != MaterialModel::Linear || &sc.materialOf(p.id[k + 1]) != &mat ||
        &sc.materialOf(p.id[k + 2]) != &mat || &sc.materialOf(p.id[k + 3]) != &mat) {
      physics::updateDeformation<3>(sc, p, L + 9 * (k - k0), dt, k, k + 1);
      ++k;
      continue;
    }
    V4 Lk[9], F[9], Fn[9], S[6];
    loadTensors4(L + 9 * (k - k0), Lk);
    loadTensors4(p.F + 9 * k, F);
    // physics::updateDeformation<3>: F += dt product<3>(L, F), entry (i, j) summed over m in order
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        Fn[3 * i + j] = F[3 * i + j] + DT * (Lk[3 * i] * F[j] + Lk[3 * i + 1] * F[3 + j] +
                                             Lk[3 * i + 2] * F[6 + j]);
    storeTensors4(p.F + 9 * k, Fn);
    // determinant<3>, expanded along the first row
    const V4 det = Fn[0] * (Fn[4] * Fn[8] - Fn[5] * Fn[7]) -
                   Fn[1] * (Fn[3] * Fn[8] - Fn[5] * Fn[6]) +
                   Fn[2] * (Fn[3] * Fn[7] - Fn[4] * Fn[6]);
    _mm256_storeu_pd(p.V + k, det * _mm256_loadu_pd(p.V0 + k));
    // material::jaumannUpdate (3D): the spin a, b, c and the six new entries in closed form
    loadStress4(p.s + kStress<3> * k, S); // (Voigt: xx, yy, zz, yz, xz, xy)
    const V4 a = HALF * (Lk[1] - Lk[3]), b = HALF * (Lk[2] - Lk[6]), c = HALF * (Lk[5] - Lk[7]);
    const V4 s00 = S[0], s11 = S[1], s22 = S[2], s01 = S[5], s02 = S[4], s12 = S[3];
    const V4 lt = splat(mat.lambda) * (Lk[0] + Lk[4] + Lk[8]), mu2 = splat(2.0 * mat.mu),
             mu = splat(mat.mu);
    const V4 n00 = lt + mu2 * Lk[0] + TWO * (a * s01 + b * s02);
    const V4 n11 = lt + mu2 * Lk[4] + TWO * (c * s12 - a * s01);
    const V4 n22 = lt + mu2 * Lk[8] - TWO * (b * s02 + c * s12);
    const V4 n01 = mu * (Lk[1] + Lk[3]) + a * (s11 - s00) + b * s12 + c * s02;
    const V4 n02 = mu * (Lk[2] + Lk[6]) + b * (s22 - s00) + a * s12 - c * s01;
    const V4 n12 = mu * (Lk[5] + Lk[7]) + c * (s22 - s11) - a * s02 - b * s01;
    S[0] = s00 + DT * n00;
    S[1] = s11 + DT * n11;
    S[2] = s22 + DT * n22;
    S[3] = s12 + DT * n12;
    S[4] = s02 + DT * n02;
    S[5] = s01 + DT * n01;
    storeStress4(p.s + kStress<3> * k, S);
    if (stretch) // tracking::updateDomain: l_a = |F e_a| l0_a (Eigen's norm: x0^2 + (x1^2 + x2^2))
      for (int ax = 0; ax < 3; ++ax) {
        const V4 x0 = Fn[ax], x1 = Fn[3 + ax], x2 = Fn[6 + ax];
        storeComponent4(p.l + 3 * k, ax,
                        _mm256_sqrt_pd(x0 * x0 + (x1 * x1 + x2 * x2)) *
                            loadComponent4(p.l0 + 3 * k, ax));
      }
    k += 4;
  }
  if (k < k1) physics::updateDeformation<3>(sc, p, L + 9 * (k - k0), dt, k, k1);
}

GIMP_LANES PetscInt checkParticles(PetscInt n, const double *x, const double *l, const double *v,
                                   const double *s, const double *V, const double *lo,
                                   const double *hi, double hmax, const double *own0,
                                   const double *own1, PetscInt &bad, PetscInt64 &leaving) {
  const V4 LO = load3(lo), HI = load3(hi), O0 = load3(own0), O1 = load3(own1), HM = splat(hmax),
           zero = splat(0.0);
  bad = -1;
  for (PetscInt k = 0; k < n; ++k) {
    const V4 X = load3(x + 3 * k), L = load3(l + 3 * k);
    // 0 where the stress entries and each x_a + v_a are finite, NaN otherwise (NaN fails every
    // comparison)
    const double *sk = s + kStress<3> * k;
    const V4 Z = (X + load3(v + 3 * k)) * zero + _mm256_loadu_pd(sk) * zero +
                 splat(sk[4] * 0.0 + sk[5] * 0.0);
    const V4 mine =
        _mm256_and_pd(_mm256_cmp_pd(X, O0, _CMP_GE_OQ), _mm256_cmp_pd(X, O1, _CMP_LT_OQ));
    leaving += (_mm256_movemask_pd(mine) & 7) != 7;
    if (bad >= 0) continue;
    V4 ok = _mm256_cmp_pd(Z, zero, _CMP_EQ_OQ);
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(X - L, LO, _CMP_GE_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(X + L, HI, _CMP_LE_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(L, zero, _CMP_GT_OQ));
    ok = _mm256_and_pd(ok, _mm256_cmp_pd(L, HM, _CMP_LE_OQ));
    if ((_mm256_movemask_pd(ok) & 7) != 7 || !(V[k] > 0 && V[k] <= DBL_MAX)) bad = k;
  }
  return n;
}

#else // no lanes on this architecture (laneLoops::available() is false): the scalar loops

void internalForce(const Stencils<3> &st, PetscInt n, const double *V, const double *stress,
                   double *f) {
  transfer::internalForce<3>(st, 0, n, V, stress, f);
}
void velocityGradients(const Stencils<3> &st, PetscInt k0, PetscInt k1, const double *vg,
                       double *L) {
  for (PetscInt k = k0; k < k1; ++k)
    tensorAt<3>(L, k - k0) = velocityGradientAt<3>(st, k, vg);
}
void updateDeformation(const Scene<3> &sc, ParticleView<3> &p, const double *L, double dt,
                       PetscInt k0, PetscInt k1) {
  physics::updateDeformation<3>(sc, p, L, dt, k0, k1);
}

PetscInt checkParticles(PetscInt, const double *, const double *, const double *, const double *,
                        const double *, const double *, const double *, double, const double *,
                        const double *, PetscInt &bad, PetscInt64 &) {
  bad = -1;
  return 0; // none tested: Solver::checks tests them in its own loop
}

#endif

} // namespace gimp::transfer::laneLoops
