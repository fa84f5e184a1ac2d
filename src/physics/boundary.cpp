#include "gimp/physics/boundary.hpp"

#include "gimp/physics/mms.hpp"
#include "gimp/physics/tracking.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

namespace gimp::physics {

namespace {

/// Particle k's face normal to reference axis a on side n: its coordinate (GIMP's box face), its
/// area and, with CPDI (2D), its midpoint. The geometry of a face is per dimension:
///   2D: an edge; GIMP's spans 2 halfLength across a, times the thickness; a CPDI edge is the
///       segment between its two corners, of its current length;
///   3D: GIMP's face spans 2 l along each of the other two axes (the traction's dead load: the
///       initial face, or its part inside the traction's disk).
template <int D> struct ParticleFace {
  double at = 0, area = 0, mid[D] = {};
  bool cpdi = false;
};

/// The 2D edge, halfLength its half-length across a.
ParticleFace<2> edgeOf(const Scene<2> &sc, const ParticleView<2> &p, PetscInt k, int a, double n,
                       double halfLength) {
  ParticleFace<2> E;
  E.at = p.x[2 * k + a] + n * p.l[2 * k + a];
  E.area = 2.0 * halfLength * sc.material.thickness;
  if (!usesCpdi(sc.tracking)) return E;
  double own[8];
  const double *c = &p.corners[8 * k];
  if (sc.tracking == Tracking::Cpdi) {
    tracking::cpdiParallelogram(p, k, own);
    c = own;
  }
  int c1, c2;
  edgeCorners(a, n, c1, c2);
  E.cpdi = true;
  E.area = std::hypot(c[2 * c2] - c[2 * c1], c[2 * c2 + 1] - c[2 * c1 + 1]) * sc.material.thickness;
  for (int d = 0; d < 2; ++d)
    E.mid[d] = 0.5 * (c[2 * c1 + d] + c[2 * c2 + d]);
  return E;
}

/// A 3D CPDI particle's face normal to reference axis a on side n: the quadrilateral of its four
/// corners there, its vector area's length and its centre.
ParticleFace<3> cpdiFace(const Scene<3> &sc, const ParticleView<3> &p, PetscInt k, int a,
                         double n) {
  double own[24];
  const double *c = &p.corners[24 * k];
  if (sc.tracking == Tracking::Cpdi) {
    tracking::cpdiParallelogram<3>(p, k, own);
    c = own;
  }
  const int *q = faceCorners(a, n);
  ParticleFace<3> f;
  f.cpdi = true;
  double d1[3], d2[3];
  for (int d = 0; d < 3; ++d) {
    d1[d] = c[3 * q[2] + d] - c[3 * q[0] + d];
    d2[d] = c[3 * q[3] + d] - c[3 * q[1] + d];
    f.mid[d] = 0.25 * (c[3 * q[0] + d] + c[3 * q[1] + d] + c[3 * q[2] + d] + c[3 * q[3] + d]);
  }
  const double cx = d1[1] * d2[2] - d1[2] * d2[1], cy = d1[2] * d2[0] - d1[0] * d2[2],
               cz = d1[0] * d2[1] - d1[1] * d2[0];
  f.area = 0.5 * std::sqrt(cx * cx + cy * cy + cz * cz);
  f.at = f.mid[a];
  return f;
}

/// The face a traction loads: in 2D the edge of the initial length (a dead load); in 3D the
/// initial face, or its part inside the traction's disk (in-face coordinates in axis order).
ParticleFace<2> tractionFace(const Scene<2> &sc, const ParticleView<2> &p, PetscInt k, int a,
                             const Traction<2> &tr) {
  return edgeOf(sc, p, k, a, tr.normal(), p.l0[2 * k + 1 - a]);
}
ParticleFace<3> tractionFace(const Scene<3> &sc, const ParticleView<3> &p, PetscInt k, int a,
                             const Traction<3> &tr) {
  ParticleFace<3> f;
  const int b1 = (a + 1) % 3, b2 = (a + 2) % 3, c1 = std::min(b1, b2), c2 = std::max(b1, b2);
  const double *X = p.X0 + 3 * k, *l0 = p.l0 + 3 * k;
  f.area = tr.loadedArea(X[c1] - l0[c1], X[c1] + l0[c1], X[c2] - l0[c2], X[c2] + l0[c2]);
  f.at = p.x[3 * k + a] + tr.normal() * p.l[3 * k + a];
  if (!usesCpdi(sc.tracking)) return f;
  // CPDI: the traction acts on the current face, its loaded share as of the initial face's.
  const double share = f.area / (4.0 * l0[c1] * l0[c2]);
  f = cpdiFace(sc, p, k, a, tr.normal());
  f.area *= share;
  return f;
}

/// The face a penalty condition acts on, in the current configuration.
ParticleFace<2> penaltyFace(const Scene<2> &sc, const ParticleView<2> &p, PetscInt k, int a,
                            double n) {
  return edgeOf(sc, p, k, a, n, p.l[2 * k + 1 - a]);
}
ParticleFace<3> penaltyFace(const Scene<3> &sc, const ParticleView<3> &p, PetscInt k, int a,
                            double n) {
  if (usesCpdi(sc.tracking)) return cpdiFace(sc, p, k, a, n);
  ParticleFace<3> f;
  const int b1 = (a + 1) % 3, b2 = (a + 2) % 3;
  f.area = 4.0 * p.l[3 * k + b1] * p.l[3 * k + b2];
  f.at = p.x[3 * k + a] + n * p.l[3 * k + a];
  return f;
}

/// The displacement of particle k's face on axis a, side n, component c: u_p + (F - I) n l0
/// (exact for a uniformly strained particle); CPDI: the displacement of the edge's midpoint.
template <int D>
double faceDisplacement(const ParticleView<D> &p, PetscInt k, const ParticleFace<D> &E, int a,
                        double n, int c) {
  if (E.cpdi) return E.mid[c] - p.X0[D * k + c] - (c == a ? n * p.l0[D * k + a] : 0.0);
  const auto F = tensorAt<D>(p.F, k);
  return p.x[D * k + c] - p.X0[D * k + c] + (F(c, a) - (c == a ? 1.0 : 0.0)) * n * p.l0[D * k + a];
}

/// The largest modulus (lambda* + 2 mu) and lightest density of the bodies: the penalty acts on
/// the faces of every body with one alpha.
template <int D> void stiffest(const Scene<D> &sc, double &M, double &rho) {
  M = sc.material.lambdaStar + 2.0 * sc.material.mu;
  rho = sc.material.rho;
  if (sc.oneMaterial) return;
  M = 0;
  rho = 1e300;
  for (const Body<D> &b : sc.bodies) {
    M = std::max(M, b.material.lambdaStar + 2.0 * b.material.mu);
    rho = std::min(rho, b.material.rho);
  }
}

} // namespace

template <int D>
PetscErrorCode Boundary<D>::setup(MPI_Comm comm, const Scene<D> &sc, const Lattice<D> &grid,
                                  double dt, bool constantBounds) {
  active_ = sc.hasExternalForces();
  if (sc.dbcs.empty()) return PETSC_SUCCESS;
  // The penalty spring on a boundary node (alpha h^(D-1) against a mass of about rho h^D / 2)
  // is stable for alpha < 2 rho h / dt^2.
  double M = 0, rho = 0;
  stiffest(sc, M, rho);
  const double h = grid.hMin();
  // Measured on the slab: stable at 0.83 of 2 rho h / dt^2, unstable at 0.92 of it.
  const double limit = 1.6 * rho * h / (dt * dt);
  double worst = 0, weakest = 1e300;
  for (const DisplacementBC<D> &d : sc.dbcs) {
    worst = std::max(worst, d.penaltyScale);
    weakest = std::min(weakest, d.penaltyScale);
  }
  const char *part = D == 2 ? "segment" : "face";
  if (sc.penalty == 0) {
    alpha_ = std::min(100.0 * M / h, 0.5 * rho * h / (dt * dt));
  } else {
    alpha_ = sc.penalty;
    if (constantBounds && alpha_ * worst > limit)
      throw InputError("option -gimp_penalty " + formatNumber(sc.penalty) + ": with the largest " +
                       part + " scale " + formatNumber(worst) +
                       " it exceeds the stable limit 1.6 rho h_min / dt^2 = " +
                       formatNumber(limit) + " Pa/m for -ts_dt " + formatNumber(dt));
  }
  // Without its symmetric counterpart, the traction term of Eq. 9 needs a penalty that
  // dominates it: measured unstable at 1 M / h_min and stable from 2 M / h_min on.
  if (constantBounds && sc.penaltyTraction && alpha_ * weakest < 4.0 * M / h)
    throw InputError("option -gimp_penalty " + formatNumber(alpha_) + ": with the smallest " +
                     part + " scale " + formatNumber(weakest) +
                     " it is below 4 M / h_min = " + formatNumber(4.0 * M / h) +
                     " Pa/m, where the traction term of Eq. 9 goes unstable; raise it, or use "
                     "-gimp_penalty_traction false");
  reactions_.assign(D * sc.dbcs.size(), 0.0);
  gaps_.assign(sc.dbcs.size(), 0.0);
  maxGap_.assign(sc.dbcs.size(), 0.0);
  PetscCall(PetscPrintf(comm, "gimp: penalty alpha = %.6g Pa/m (%.3g M / h_min)\n", alpha_,
                        alpha_ * h / M));
  return PETSC_SUCCESS;
}

template <int D>
void Boundary<D>::externalForces(const Scene<D> &sc, const Grid<D> &g, const Stencils<D> &st,
                                 const ParticleView<D> &p, double t, double *fe,
                                 const double *scale) {
  bool gravity = false;
  for (int c = 0; c < D; ++c)
    gravity = gravity || sc.gravity[c] != 0;
  std::unique_ptr<mms::AxialWave> ex;
  if (sc.mms == Mms::AxialWave) ex = std::make_unique<mms::AxialWave>(sc);
  std::vector<double> factor(sc.tractions.size());
  for (size_t q = 0; q < factor.size(); ++q)
    factor[q] = sc.tractions[q].ramp.at(t);
  for (PetscInt k = 0; k < p.n; ++k) {
    // Body force, Eq. 8: f_i = sum_p m_p b S_ip (b with the manufactured solution's force).
    if (gravity || ex) {
      const double mk = scale ? scale[k] * p.m[k] : p.m[k];
      double fb[D];
      for (int c = 0; c < D; ++c)
        fb[c] = mk * (sc.gravity[c] + (c == 0 && ex ? ex->bodyForce(p.X0[D * k], t) : 0.0));
      st.forEach(k, [&](PetscInt nd, double w, const Vector<D> &) {
        for (int c = 0; c < D; ++c)
          fe[D * nd + c] += w * fb[c];
      });
    }
    // Tractions, Eq. 8. GIMP: a dead load, whose resultant is the traction times the initial
    // face area. CPDI (2D): the traction (force per current area, global components) acts on the
    // current edge between the corners, its resultant the traction times the current length.
    for (int a = 0; a < D && p.trac; ++a) {
      const PetscInt q = p.trac[D * k + a];
      if (q < 0) continue;
      const Traction<D> &tr = sc.tractions[q];
      const ParticleFace<D> E = tractionFace(sc, p, k, a, tr);
      const double area = scale ? scale[k] * E.area : E.area;
      double force[D];
      for (int c = 0; c < D; ++c)
        force[c] = tr.value[c] * factor[q] * area;
      spreadFaceForce(g, st, k, a, tr.normal(), E.at, force, fe);
    }
  }
  if (!sc.dbcs.empty()) penaltyForces(sc, g, st, p, t, fe);
}

template <int D>
void Boundary<D>::penaltyForces(const Scene<D> &sc, const Grid<D> &g, const Stencils<D> &st,
                                const ParticleView<D> &p, double t, double *fe) {
  // Eq. 9 on each particle face that lies on a constrained face, per constrained component.
  std::vector<double> ubar(D * sc.dbcs.size());
  for (size_t q = 0; q < sc.dbcs.size(); ++q)
    for (int c = 0; c < D; ++c)
      ubar[D * q + c] = sc.dbcs[q].u[c].valueOr0(t);
  reactions_.assign(D * sc.dbcs.size(), 0.0);
  gaps_.assign(sc.dbcs.size(), 0.0);
  maxGap_.resize(sc.dbcs.size(), 0.0);
  for (PetscInt k = 0; k < p.n; ++k)
    for (int a = 0; a < D; ++a) {
      const PetscInt q = p.dbc[D * k + a];
      if (q < 0) continue;
      const DisplacementBC<D> &d = sc.dbcs[q];
      const double n = d.normal();
      const ParticleFace<D> E = penaltyFace(sc, p, k, a, n);
      const Tensor<D> sg = stressAt<D>(p.s, k);
      const double alpha = alpha_ * d.penaltyScale;
      double force[D] = {};
      for (int c = 0; c < D; ++c) {
        if (!d.fix[c]) continue;
        const double u = faceDisplacement(p, k, E, a, n, c);
        const double sigmaCA = sc.penaltyTraction ? sg(c, a) : 0.0;
        force[c] = (sigmaCA * n - alpha * (u - ubar[D * q + c])) * E.area;
        gaps_[q] = std::max(gaps_[q], std::fabs(u - ubar[D * q + c]));
        reactions_[D * q + c] += force[c];
      }
      spreadFaceForce(g, st, k, a, n, E.at, force, fe);
    }
}

template <int D>
void Boundary<D>::penaltyIncrement(const Scene<D> &sc, const Grid<D> &g, const Stencils<D> &st,
                                   const ParticleView<D> &p, const double *du, const double *L,
                                   const double *ds, bool springs, double *fe) const {
  // The linearisation of penaltyForces: the same faces, areas and face shapes. Each input may
  // be null: its part is left out.
  if (!p.dbc) return; // no penalty condition in the scene
  for (PetscInt k = 0; k < p.n; ++k)
    for (int a = 0; a < D; ++a) {
      const PetscInt q = p.dbc[D * k + a];
      if (q < 0) continue;
      const DisplacementBC<D> &d = sc.dbcs[q];
      const double n = d.normal();
      const ParticleFace<D> E = penaltyFace(sc, p, k, a, n);
      double dU[D] = {}; // the face's displacement: the particle's, as G2P moves it ...
      if (du)
        st.forEach(k, [&](PetscInt nd, double w, const Vector<D> &) {
          for (int c = 0; c < D; ++c)
            dU[c] += w * du[D * nd + c];
        });
      if (L) { // ... and the change of F, dF = L F
        const Tensor<D> dF = product<D>(tensorAt<D>(L, k), tensorAt<D>(p.F, k));
        for (int c = 0; c < D; ++c)
          dU[c] += dF(c, a) * n * p.l0[D * k + a];
      }
      const double alpha = springs ? alpha_ * d.penaltyScale : 0.0;
      const bool withTraction = ds && sc.penaltyTraction;
      const Tensor<D> dsk = withTraction ? stressAt<D>(ds, k) : Tensor<D>::Zero();
      double force[D] = {};
      for (int c = 0; c < D; ++c) {
        if (!d.fix[c]) continue;
        const double traction = withTraction ? dsk(c, a) * n : 0.0;
        force[c] = (traction - alpha * dU[c]) * E.area;
      }
      spreadFaceForce(g, st, k, a, n, E.at, force, fe);
    }
}

template <int D>
PetscErrorCode Boundary<D>::lastReactions(MPI_Comm comm, std::vector<double> &force,
                                          std::vector<double> &gap) const {
  force.assign(reactions_.size(), 0.0);
  gap.assign(gaps_.size(), 0.0);
  if (reactions_.empty()) return PETSC_SUCCESS;
  PetscCallMPI(MPI_Allreduce(reactions_.data(), force.data(), static_cast<int>(force.size()),
                             MPI_DOUBLE, MPI_SUM, comm));
  PetscCallMPI(MPI_Allreduce(gaps_.data(), gap.data(), static_cast<int>(gap.size()), MPI_DOUBLE,
                             MPI_MAX, comm));
  return PETSC_SUCCESS;
}

template <int D>
PetscErrorCode Boundary<D>::reactions(MPI_Comm comm, std::vector<double> &force,
                                      std::vector<double> &gap) {
  PetscCall(lastReactions(comm, force, gap));
  for (size_t q = 0; q < gap.size(); ++q)
    maxGap_[q] = std::max(maxGap_[q], gap[q]);
  return PETSC_SUCCESS;
}

template <int D>
void Boundary<D>::restore(const std::vector<double> &maxGap, const std::vector<double> &force,
                          const std::vector<double> &gap, bool root) {
  maxGap_ = maxGap;
  // The sums over ranks on one rank, zeros on the others: the reductions give them back exactly.
  reactions_.assign(force.size(), 0.0);
  gaps_.assign(gap.size(), 0.0);
  if (root) {
    reactions_ = force;
    gaps_ = gap;
  }
}

template class Boundary<2>;
template class Boundary<3>;

} // namespace gimp::physics
