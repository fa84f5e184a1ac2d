#include "gimp/physics/boundary.hpp"

#include "gimp/physics/mms.hpp"
#include "gimp/physics/tracking.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

namespace gimp::physics {

namespace {

/// Particle k's edge normal to reference axis a on side n: its coordinate (GIMP's box edge),
/// its length times the thickness and, with CPDI, its midpoint. GIMP's edge spans 2 halfLength
/// across a; a CPDI edge is the segment between its two corners, of its current length.
struct Edge {
  double coord = 0, len = 0, mid[2] = {0, 0};
  bool cpdi = false;
};

Edge edgeOf(const Scene<2> &sc, const ParticleView<2> &p, PetscInt k, int a, double n,
            double halfLength) {
  Edge E;
  E.coord = p.x[2 * k + a] + n * p.l[2 * k + a];
  E.len = 2.0 * halfLength * sc.material.thickness;
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
  E.len = std::hypot(c[2 * c2] - c[2 * c1], c[2 * c2 + 1] - c[2 * c1 + 1]) * sc.material.thickness;
  for (int d = 0; d < 2; ++d)
    E.mid[d] = 0.5 * (c[2 * c1 + d] + c[2 * c2 + d]);
  return E;
}

} // namespace

PetscErrorCode Boundary::setup(MPI_Comm comm, const Scene<2> &sc, const Lattice<2> &grid, double dt,
                               bool constantBounds) {
  active_ = !sc.tractions.empty() || !sc.dbcs.empty() || sc.gravity[0] != 0 || sc.gravity[1] != 0 ||
            sc.mms != Mms::None;
  if (sc.dbcs.empty()) return PETSC_SUCCESS;
  // The penalty spring on a boundary node (alpha h per unit thickness against a mass of about
  // rho h^2 / 2) is stable for alpha < 2 rho h / dt^2.
  // With several materials: the stiffest modulus and the lightest density (the penalty acts on
  // the edges of every body with one alpha).
  double M = sc.material.lambdaStar + 2.0 * sc.material.mu, rho = sc.material.rho;
  if (!sc.oneMaterial) { // every body carries its own material
    M = 0;
    rho = 1e300;
    for (const Body<2> &b : sc.bodies) {
      M = std::max(M, b.material.lambdaStar + 2.0 * b.material.mu);
      rho = std::min(rho, b.material.rho);
    }
  }
  const double h = grid.hMin();
  // Measured on the slab: stable at 0.83 of 2 rho h / dt^2, unstable at 0.92 of it.
  const double limit = 1.6 * rho * h / (dt * dt);
  double worst = 0, weakest = 1e300;
  for (const DisplacementBC<2> &d : sc.dbcs) {
    worst = std::max(worst, d.penaltyScale);
    weakest = std::min(weakest, d.penaltyScale);
  }
  if (sc.penalty == 0) {
    alpha_ = std::min(100.0 * M / h, 0.5 * rho * h / (dt * dt));
  } else {
    alpha_ = sc.penalty;
    if (constantBounds && alpha_ * worst > limit)
      throw InputError("option -gimp_penalty " + formatNumber(sc.penalty) +
                       ": with the largest segment scale " + formatNumber(worst) +
                       " it exceeds the stable limit 1.6 rho h_min / dt^2 = " +
                       formatNumber(limit) + " Pa/m for -ts_dt " + formatNumber(dt));
  }
  // Without its symmetric counterpart, the traction term of Eq. 9 needs a penalty that
  // dominates it: measured unstable at 1 M / h_min and stable from 2 M / h_min on.
  if (constantBounds && sc.penaltyTraction && alpha_ * weakest < 4.0 * M / h)
    throw InputError("option -gimp_penalty " + formatNumber(alpha_) +
                     ": with the smallest segment scale " + formatNumber(weakest) +
                     " it is below 4 M / h_min = " + formatNumber(4.0 * M / h) +
                     " Pa/m, where the traction term of Eq. 9 goes unstable; raise it, or use "
                     "-gimp_penalty_traction false");
  reactions_.assign(2 * sc.dbcs.size(), 0.0);
  gaps_.assign(sc.dbcs.size(), 0.0);
  maxGap_.assign(sc.dbcs.size(), 0.0);
  PetscCall(PetscPrintf(comm, "gimp: penalty alpha = %.6g Pa/m (%.3g M / h_min)\n", alpha_,
                        alpha_ * h / M));
  return PETSC_SUCCESS;
}

void Boundary::externalForces(const Scene<2> &sc, const Grid<2> &g, const Stencils<2> &st,
                              const ParticleView<2> &p, double t, double *fe, const double *scale) {
  const double gxv = sc.gravity[0], gyv = sc.gravity[1];
  const bool gravity = gxv != 0 || gyv != 0;
  std::unique_ptr<mms::Skb1d> ex;
  if (sc.mms == Mms::AxialWave) ex = std::make_unique<mms::Skb1d>(sc);
  std::vector<double> factor(sc.tractions.size());
  for (size_t q = 0; q < factor.size(); ++q)
    factor[q] = sc.tractions[q].ramp.at(t);
  for (PetscInt k = 0; k < p.n; ++k) {
    // Body force, Eq. 8: f_i = sum_p m_p b S_ip.
    if (gravity || ex) {
      const double bx = gxv + (ex ? ex->bodyForce(p.X0[2 * k], t) : 0.0);
      const double mk = scale ? scale[k] * p.m[k] : p.m[k];
      const double fx = mk * bx, fy = mk * gyv;
      st.forEach(k, [&](PetscInt nd, double w, const Vector<2> &) {
        fe[2 * nd] += w * fx;
        fe[2 * nd + 1] += w * fy;
      });
    }
    // Tractions, Eq. 8. GIMP: a dead load, whose resultant is the traction times the initial
    // edge length. CPDI: the traction (force per current area, global components) acts on the
    // current edge between the corners, its resultant the traction times the current length.
    for (int a = 0; a < 2 && p.trac; ++a) {
      const PetscInt q = p.trac[2 * k + a];
      if (q < 0) continue;
      const Traction<2> &tr = sc.tractions[q];
      const Edge E = edgeOf(sc, p, k, a, tr.normal(), p.l0[2 * k + 1 - a]);
      const double len = scale ? scale[k] * E.len : E.len;
      const double force[2] = {tr.value[0] * factor[q] * len, tr.value[1] * factor[q] * len};
      spreadEdgeForce(g, st, k, a, tr.normal(), E.coord, force, fe);
    }
  }
  if (!sc.dbcs.empty()) penaltyForces(sc, g, st, p, t, fe);
}

void Boundary::penaltyForces(const Scene<2> &sc, const Grid<2> &g, const Stencils<2> &st,
                             const ParticleView<2> &p, double t, double *fe) {
  // Eq. 9 on each particle edge that lies on a constrained segment, per constrained component.
  // u is the displacement of the edge, u_p + (F - I) n l0: exact for a uniformly strained
  // particle.
  std::vector<double> ubar(2 * sc.dbcs.size());
  for (size_t q = 0; q < sc.dbcs.size(); ++q)
    for (int c = 0; c < 2; ++c)
      ubar[2 * q + c] = sc.dbcs[q].u[c].valueOr0(t);
  reactions_.assign(2 * sc.dbcs.size(), 0.0);
  gaps_.assign(sc.dbcs.size(), 0.0);
  maxGap_.resize(sc.dbcs.size(), 0.0);
  for (PetscInt k = 0; k < p.n; ++k)
    for (int a = 0; a < 2; ++a) {
      const PetscInt q = p.dbc[2 * k + a];
      if (q < 0) continue;
      const DisplacementBC<2> &d = sc.dbcs[q];
      const double n = d.normal();
      const Edge E = edgeOf(sc, p, k, a, n, p.l[2 * k + 1 - a]);
      const double len = E.len;
      const auto F = tensorAt<2>(p.F, k), sg = tensorAt<2>(p.s, k);
      const double alpha = alpha_ * d.penaltyScale;
      double force[2] = {0, 0};
      for (int c = 0; c < 2; ++c) {
        if (!d.fix[c]) continue;
        // CPDI: the displacement of the edge's midpoint (the same for cpdi's parallelogram).
        const double u = E.cpdi ? E.mid[c] - p.X0[2 * k + c] - (c == a ? n * p.l0[2 * k + a] : 0.0)
                                : p.x[2 * k + c] - p.X0[2 * k + c] +
                                      (F(c, a) - (c == a ? 1.0 : 0.0)) * n * p.l0[2 * k + a];
        const double sigmaCA = sc.penaltyTraction ? sg(c, a) : 0.0;
        force[c] = (sigmaCA * n - alpha * (u - ubar[2 * q + c])) * len;
        gaps_[q] = std::max(gaps_[q], std::fabs(u - ubar[2 * q + c]));
        reactions_[2 * q + c] += force[c];
      }
      spreadEdgeForce(g, st, k, a, n, E.coord, force, fe);
    }
}

void Boundary::penaltyIncrement(const Scene<2> &sc, const Grid<2> &g, const Stencils<2> &st,
                                const ParticleView<2> &p, const double *du, const double *L,
                                const double *ds, bool springs, double *fe) const {
  // The linearisation of penaltyForces: the same edges, lengths and edge shapes. Each input may
  // be null: its part is left out.
  if (!p.dbc) return; // no penalty condition in the scene
  for (PetscInt k = 0; k < p.n; ++k)
    for (int a = 0; a < 2; ++a) {
      const PetscInt q = p.dbc[2 * k + a];
      if (q < 0) continue;
      const DisplacementBC<2> &d = sc.dbcs[q];
      const double n = d.normal();
      const Edge E = edgeOf(sc, p, k, a, n, p.l[2 * k + 1 - a]);
      const double len = E.len;
      double dU[2] = {0, 0}; // the edge's displacement: the particle's, as G2P moves it ...
      if (du)
        st.forEach(k, [&](PetscInt nd, double w, const Vector<2> &) {
          for (int c = 0; c < 2; ++c)
            dU[c] += w * du[2 * nd + c];
        });
      if (L) { // ... and the change of F, dF = L F
        const Tensor<2> dF = product<2>(tensorAt<2>(L, k), tensorAt<2>(p.F, k));
        for (int c = 0; c < 2; ++c)
          dU[c] += dF(c, a) * n * p.l0[2 * k + a];
      }
      const double alpha = springs ? alpha_ * d.penaltyScale : 0.0;
      double force[2] = {0, 0};
      for (int c = 0; c < 2; ++c) {
        if (!d.fix[c]) continue;
        const double traction = ds && sc.penaltyTraction ? ds[4 * k + 2 * c + a] * n : 0.0;
        force[c] = (traction - alpha * dU[c]) * len;
      }
      spreadEdgeForce(g, st, k, a, n, E.coord, force, fe);
    }
}

PetscErrorCode Boundary::lastReactions(MPI_Comm comm, std::vector<double> &force,
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

PetscErrorCode Boundary::reactions(MPI_Comm comm, std::vector<double> &force,
                                   std::vector<double> &gap) {
  PetscCall(lastReactions(comm, force, gap));
  for (size_t q = 0; q < gap.size(); ++q)
    maxGap_[q] = std::max(maxGap_[q], gap[q]);
  return PETSC_SUCCESS;
}

void Boundary::restore(const std::vector<double> &maxGap, const std::vector<double> &force,
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

} // namespace gimp::physics
