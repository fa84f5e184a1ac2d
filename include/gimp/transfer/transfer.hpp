// Particle <-> grid transfers as free kernels over explicit arrays, for any dimension D. They
// read the stencils through Stencils::forEach (rows or blocks alike).
//
// Nodal arrays are the window arrays of one rank: D values per slot (see grid/stencils.hpp);
// nodal mass is stored in component 0 of its slot, in the layout of the momentum. Particle
// arrays are those of a ParticleView. No kernel knows about PETSc objects, levels or ranks.
#pragma once

#include "gimp/core/pair.hpp"
#include "gimp/grid/stencils.hpp"

namespace gimp::transfer {

/// P2G of particle k: S_ip m_p v_p into mom and, when mass is not null, S_ip m_p into component 0
/// of mass (accumulated).
template <int D>
GIMP_ALWAYS_INLINE void particleToGrid(const Stencils<D> &st, PetscInt k, double mp,
                                       const double *vk, double *mom, double *mass) {
  double pk[D];
  for (int c = 0; c < D; ++c)
    pk[c] = mp * vk[c];
  if constexpr (D == 2)
    if (st.isBlock(k)) { // a sum along x for each row of nodes, both components at once
      using simd::Pair;
      // Everything read before the first store (which the compiler cannot tell from the block).
      const Block<2> &b = st.block(k);
      const Pair p2 = {pk[0], pk[1]};
      double wx[3], wy[3];
      Pair w2[3];
      PetscInt row[3];
      for (int i = 0; i < 3; ++i) {
        wx[i] = b.w[0][i];
        wy[i] = b.w[1][i];
        w2[i] = simd::splat(wx[i]);
        row[i] = 2 * (b.base + i * b.stride[0]);
      }
      for (int j = 0; j < 3; ++j) {
        const double am = wy[j] * mp;
        const Pair a = wy[j] * p2;
        for (int i = 0; i < 3; ++i)
          simd::addTo(mom + row[j] + 2 * i, w2[i] * a);
        if (mass)
          for (int i = 0; i < 3; ++i)
            mass[row[j] + 2 * i] += wx[i] * am;
      }
      return;
    }
  st.forEach(k, [&](PetscInt nd, double w, const Vector<D> &) {
    for (int c = 0; c < D; ++c)
      mom[D * nd + c] += w * pk[c];
    if (mass) mass[D * nd] += w * mp;
  });
}

/// P2G: nodal momentum sum_p S_ip m_p v_p into mom and, when mass is not null, nodal mass
/// sum_p S_ip m_p into component 0 of mass. Both are accumulated (the caller zeroes them).
template <int D>
void particlesToGrid(const Stencils<D> &st, PetscInt n, const double *m, const double *v,
                     double *mom, double *mass) {
  for (PetscInt k = 0; k < n; ++k)
    particleToGrid<D>(st, k, m[k], v + D * k, mom, mass);
}

/// The grid velocity vp and acceleration ap at particle k.
template <int D>
GIMP_ALWAYS_INLINE void particleFromGrid(const Stencils<D> &st, PetscInt k, const double *vg,
                                         const double *ag, double *vp, double *ap) {
  for (int c = 0; c < D; ++c)
    vp[c] = ap[c] = 0.0;
  if constexpr (D == 2)
    if (st.isBlock(k)) { // both components at once
      using simd::Pair;
      const Block<2> &b = st.block(k);
      Pair v = {0, 0}, a = {0, 0};
      for (int j = 0; j < 3; ++j) {
        const PetscInt r = 2 * (b.base + j * b.stride[0]);
        const Pair tv = b.w[0][0] * simd::load(vg + r) + b.w[0][1] * simd::load(vg + r + 2) +
                        b.w[0][2] * simd::load(vg + r + 4);
        const Pair ta = b.w[0][0] * simd::load(ag + r) + b.w[0][1] * simd::load(ag + r + 2) +
                        b.w[0][2] * simd::load(ag + r + 4);
        v += b.w[1][j] * tv;
        a += b.w[1][j] * ta;
      }
      simd::store(vp, v);
      simd::store(ap, a);
      return;
    }
  st.forEach(k, [&](PetscInt nd, double w, const Vector<D> &) {
    for (int c = 0; c < D; ++c) {
      vp[c] += w * vg[D * nd + c];
      ap[c] += w * ag[D * nd + c];
    }
  });
}

/// G2P of one rate class of a multi-rate step (docs/method.md, "Multi-rate time steps per
/// level"): v_p <- flip v_p + S u and x_p += dt S w, with u the class's velocity update field
/// (flip times its summed grid velocity increments plus (1 - flip) times the end velocity) and w
/// the mean grid velocity over its step dt. With mom, the new momenta are re-projected with the
/// same stencils (accumulated).
template <int D>
void gridToParticlesRated(const Stencils<D> &st, PetscInt n, const double *ug, const double *wg,
                          double dt, double flip, const double *m, double *v, double *x,
                          double *mom) {
  for (PetscInt k = 0; k < n; ++k) {
    double up[D], wp[D];
    particleFromGrid<D>(st, k, ug, wg, up, wp);
    for (int c = 0; c < D; ++c) {
      v[D * k + c] = flip * v[D * k + c] + up[c];
      x[D * k + c] += dt * wp[c];
    }
    if (mom) particleToGrid<D>(st, k, m[k], v + D * k, mom, nullptr);
  }
}

/// The nodal field f at particle k: fp = sum_i S_ip f_i (D values).
template <int D>
GIMP_ALWAYS_INLINE void interpolateAt(const Stencils<D> &st, PetscInt k, const double *fg,
                                      double *fp) {
  for (int c = 0; c < D; ++c)
    fp[c] = 0.0;
  if constexpr (D == 2)
    if (st.isBlock(k)) { // both components at once
      using simd::Pair;
      const Block<2> &b = st.block(k);
      Pair f = {0, 0};
      for (int j = 0; j < 3; ++j) {
        const PetscInt r = 2 * (b.base + j * b.stride[0]);
        f += b.w[1][j] * (b.w[0][0] * simd::load(fg + r) + b.w[0][1] * simd::load(fg + r + 2) +
                          b.w[0][2] * simd::load(fg + r + 4));
      }
      simd::store(fp, f);
      return;
    }
  st.forEach(k, [&](PetscInt nd, double w, const Vector<D> &) {
    for (int c = 0; c < D; ++c)
      fp[c] += w * fg[D * nd + c];
  });
}

/// G2P: each particle's velocity becomes flip (v + dt a_p) + (1 - flip) v_p with a_p and v_p
/// the grid acceleration and velocity at the particle, and it moves by dt v_p.
template <int D>
void gridToParticles(const Stencils<D> &st, PetscInt n, const double *vg, const double *ag,
                     double dt, double flip, double *v, double *x) {
  for (PetscInt k = 0; k < n; ++k) {
    double vp[D], ap[D];
    particleFromGrid<D>(st, k, vg, ag, vp, ap);
    for (int c = 0; c < D; ++c) {
      v[D * k + c] = flip * (v[D * k + c] + dt * ap[c]) + (1.0 - flip) * vp[c];
      x[D * k + c] += dt * vp[c];
    }
  }
}

/// G2P followed by the re-projection of the new momenta m_p v_p with the same stencils into mom
/// (accumulated), in one pass.
template <int D>
void gridToParticlesProjected(const Stencils<D> &st, PetscInt n, const double *vg, const double *ag,
                              double dt, double flip, const double *m, double *v, double *x,
                              double *mom) {
  for (PetscInt k = 0; k < n; ++k) {
    double vp[D], ap[D];
    particleFromGrid<D>(st, k, vg, ag, vp, ap);
    for (int c = 0; c < D; ++c) {
      v[D * k + c] = flip * (v[D * k + c] + dt * ap[c]) + (1.0 - flip) * vp[c];
      x[D * k + c] += dt * vp[c];
    }
    particleToGrid<D>(st, k, m[k], v + D * k, mom, nullptr);
  }
}

/// Velocity gradient of particle k, L = sum_i v_i (x) grad S_ip.
template <int D> Tensor<D> velocityGradientAt(const Stencils<D> &st, PetscInt k, const double *vg) {
  Tensor<D> Lk = Tensor<D>::Zero();
  if constexpr (D == 2)
    if (st.isBlock(k)) { // L(c, 0) = sum_j w_j sum_i g_i v_c, L(c, 1) = sum_j g_j sum_i w_i v_c
      using simd::Pair;  // (both components c at once)
      const Block<2> &b = st.block(k);
      Pair L0 = {0, 0}, L1 = {0, 0};
      for (int j = 0; j < 3; ++j) {
        const double *r = vg + 2 * (b.base + j * b.stride[0]);
        const Pair v0 = simd::load(r), v1 = simd::load(r + 2), v2 = simd::load(r + 4);
        const Pair pg = b.g[0][0] * v0 + b.g[0][1] * v1 + b.g[0][2] * v2;
        const Pair qw = b.w[0][0] * v0 + b.w[0][1] * v1 + b.w[0][2] * v2;
        L0 += b.w[1][j] * pg;
        L1 += b.g[1][j] * qw;
      }
      Lk << L0[0], L1[0], L0[1], L1[1];
      return Lk;
    }
  if constexpr (D == 3)
    if (st.isBlock(k)) { // rows along x: sum_i g_i v_c and sum_i w_i v_c, then the (y, z) factors
      const Block<3> b = st.block(k);
      for (int q = 0; q < 3; ++q)
        for (int j = 0; j < 3; ++j) {
          const PetscInt r = 3 * (b.base + j * b.stride[0] + q * b.stride[1]);
          double pg[3] = {0, 0, 0}, qw[3] = {0, 0, 0};
          for (int i = 0; i < 3; ++i)
            for (int c = 0; c < 3; ++c) {
              pg[c] += b.g[0][i] * vg[r + 3 * i + c];
              qw[c] += b.w[0][i] * vg[r + 3 * i + c];
            }
          const double wyz = b.w[1][j] * b.w[2][q], gy = b.g[1][j] * b.w[2][q],
                       gz = b.w[1][j] * b.g[2][q];
          for (int c = 0; c < 3; ++c) {
            Lk(c, 0) += wyz * pg[c];
            Lk(c, 1) += gy * qw[c];
            Lk(c, 2) += gz * qw[c];
          }
        }
      return Lk;
    }
  st.forEach(k, [&](PetscInt nd, double, const Vector<D> &grad) {
    for (int c = 0; c < D; ++c)
      for (int a = 0; a < D; ++a)
        Lk(c, a) += vg[D * nd + c] * grad[a];
  });
  return Lk;
}

/// Velocity gradient at each particle, row-major D x D per particle into L.
template <int D>
void velocityGradient(const Stencils<D> &st, PetscInt n, const double *vg, double *L) {
  for (PetscInt k = 0; k < n; ++k)
    tensorAt<D>(L, k) = velocityGradientAt<D>(st, k, vg);
}

} // namespace gimp::transfer
