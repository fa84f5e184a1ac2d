// External forces of Eq. 8 and the penalty displacement conditions of Eq. 9.
//
// Body force: f_i = sum_p m_p b S_ip. Tractions and penalty conditions act on particle edges
// that lie on a loaded or constrained segment of a body's side; both are integrated exactly
// along the edge by one helper, edgeShape(): the node's tent across the edge, taken at the edge,
// times the 1D weight along it. The penalty of Eq. 9 adds, per constrained component, the
// traction sigma_p n (optional) and -alpha (u - u_bar) with u the edge's displacement.
#pragma once

#include "gimp/grid/grid.hpp"
#include "gimp/grid/shape.hpp"
#include "gimp/particles/swarm.hpp"

#include <vector>

namespace gimp::physics {

/// The two corners (counter-clockwise from (-, -)) of a CPDI particle's edge normal to the
/// reference axis a on side n = +-1.
inline void edgeCorners(int a, double n, int &c1, int &c2) {
  static const int kFirst[2][2] = {{3, 1}, {0, 2}}; // [a][n > 0]
  c1 = kFirst[a][n > 0];
  c2 = (c1 + 1) % 4;
}

/// S_i of stencil entry e integrated along particle edge normal to axis a on side n = +-1, lying
/// at coordinate `edge`, per unit edge length. With CPDI stencils the edge is the segment between
/// the particle's two corners on that side and S_i linear along it (the corners' N_i averaged).
inline double edgeShape(const Grid<2> &g, const Stencils<2> &st, PetscInt e, int a, double n,
                        double edge) {
  if (st.general) {
    int c1, c2;
    edgeCorners(a, n, c1, c2);
    return 0.5 * (st.cw[4 * e + c1] + st.cw[4 * e + c2]);
  }
  const PetscInt nd = g.slotNode[st.node[e]];
  const double *z = &g.zone[4 * nd];
  return a == 0 ? shape::tent(edge - g.X[nd], z[0], z[1]) * st.w[1][e]
                : st.w[0][e] * shape::tent(edge - g.Y[nd], z[2], z[3]);
}

/// Spread a force (fx, fy) acting on particle k's edge normal to axis a on side n at `edge` onto
/// fe.
inline void spreadEdgeForce(const Grid<2> &g, const Stencils<2> &st, PetscInt k, int a, double n,
                            double edge, const double force[2], double *fe) {
  // A block: the same shape from its 1D factors (regular nodes, no cracks), over the nodes
  // forEach visits.
  auto block = [&](const auto &b) {
    st.forEach(k, [&](PetscInt nd, double, const Vector<2> &) {
      const PetscInt off = nd - b.base, j = off / b.stride[0], i = off - j * b.stride[0];
      const double *z = &g.zone[4 * nd];
      const double w = a == 0 ? shape::tent(edge - g.X[nd], z[0], z[1]) * b.w[1][j]
                              : b.w[0][i] * shape::tent(edge - g.Y[nd], z[2], z[3]);
      fe[2 * nd] += w * force[0];
      fe[2 * nd + 1] += w * force[1];
    });
  };
  if (st.isBlock(k)) return block(st.block(k));
  if (st.isBlock4(k)) return block(st.block4(k));
  for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e) {
    const double w = edgeShape(g, st, e, a, n, edge);
    fe[2 * st.node[e]] += w * force[0];
    fe[2 * st.node[e] + 1] += w * force[1];
  }
}

class Boundary {
public:
  /// The penalty alpha of Eq. 9 from -gimp_penalty or chosen from the material, grid and dt,
  /// checked against its stability bounds (the same on every rank). Prints it. With
  /// `constantBounds` false the bounds are left to the eigenvalue check (stability room).
  PetscErrorCode setup(MPI_Comm comm, const Scene<2> &sc, const Lattice<2> &grid, double dt,
                       bool constantBounds = true);

  /// The change of the penalty forces of Eq. 9 (springs and, when the scene has it, the traction
  /// term) into fe: the edge moves by du_p (du, a window array, interpolated at the particle) plus
  /// the change of F, L F n l0 (L row-major 2 x 2 per particle); the stress changes by ds. A null
  /// input leaves its part out; `springs` false leaves the springs out. Edges and lengths stay
  /// those of the current configuration.
  void penaltyIncrement(const Scene<2> &sc, const Grid<2> &g, const Stencils<2> &st,
                        const ParticleView<2> &p, const double *du, const double *L,
                        const double *ds, bool springs, double *fe) const;

  /// Whether the scene has external nodal forces (body force, tractions, penalty terms).
  bool active() const { return active_; }

  /// External nodal forces at time t accumulated into the window array fe; records each penalty
  /// condition's force on the body and its largest violation on this rank. With `scale`, each
  /// particle's body force and tractions are multiplied by its factor (a multi-rate particle's
  /// first kick in a new rate class).
  void externalForces(const Scene<2> &sc, const Grid<2> &g, const Stencils<2> &st,
                      const ParticleView<2> &p, double t, double *fe,
                      const double *scale = nullptr);

  /// Each penalty condition's force (fx, fy) summed over ranks and its largest violation
  /// |u - u_bar| at the last force evaluation; keeps the largest violation seen (collective).
  PetscErrorCode reactions(MPI_Comm comm, std::vector<double> &force, std::vector<double> &gap);
  /// The same without keeping the violation (for a checkpoint, collective).
  PetscErrorCode lastReactions(MPI_Comm comm, std::vector<double> &force,
                               std::vector<double> &gap) const;

  double alpha() const { return alpha_; }
  const std::vector<double> &maxGap() const { return maxGap_; }
  /// A run continued from a checkpoint: the largest violations so far, and the last force
  /// evaluation's forces and violations summed over ranks (held by the `root` rank).
  void restore(const std::vector<double> &maxGap, const std::vector<double> &force,
               const std::vector<double> &gap, bool root);

private:
  void penaltyForces(const Scene<2> &sc, const Grid<2> &g, const Stencils<2> &st,
                     const ParticleView<2> &p, double t, double *fe);

  bool active_ = false;
  double alpha_ = 0;              // penalty of Eq. 9 in use [Pa/m]
  std::vector<double> reactions_; // this rank's part of each condition's force (fx, fy)
  std::vector<double> gaps_;      // this rank's largest |u - u_bar| per condition
  std::vector<double> maxGap_;    // largest violation per condition over the reports
};

} // namespace gimp::physics
