// External forces of Eq. 8 and the penalty displacement conditions of Eq. 9, in 2D and 3D.
//
// Body force: f_i = sum_p m_p b S_ip. Tractions and penalty conditions act on the particle faces
// that lie on a loaded or constrained face of a body's box: in 2D a particle's edge (a face of
// one dimension less, times the thickness), in 3D a particle's face. Both are integrated exactly
// over the face by one helper, faceShape(): the node's tent across the face, taken at the face
// (Eq. 14), times the 1D weights along the face's axes. The penalty of Eq. 9 adds, per
// constrained component, the traction sigma_p n (optional) and -alpha (u - u_bar) with u the
// face's displacement. What differs with the dimension is only the geometry of a particle's face
// (its area; in 2D also CPDI's edges between tracked corners), in boundary.cpp.
#pragma once

#include "gimp/grid/cpdi_cells.hpp"
#include "gimp/grid/grid.hpp"
#include "gimp/grid/shape.hpp"
#include "gimp/input/scene.hpp"
#include "gimp/particles/swarm.hpp"

#include <array>
#include <vector>

namespace gimp::physics {

/// The two corners (counter-clockwise from (-, -)) of a 2D CPDI particle's edge normal to the
/// reference axis a on side n = +-1.
inline void edgeCorners(int a, double n, int &c1, int &c2) {
  static const int kFirst[2][2] = {{3, 1}, {0, 2}}; // [a][n > 0]
  c1 = kFirst[a][n > 0];
  c2 = (c1 + 1) % 4;
}

/// The four corners of a 3D CPDI particle's face normal to the reference axis a on side n = +-1,
/// in cyclic order around the face (grid/cpdi_cells.hpp's corner order; 4 values).
inline const int *faceCorners(int a, double n) {
  // Built once from the corner order (faceShape asks for it per stencil entry).
  static const auto table = [] {
    std::array<std::array<std::array<int, 4>, 2>, 3> t{};
    static const double s1[4] = {-1, 1, 1, -1}, s2[4] = {-1, -1, 1, 1};
    for (int ax = 0; ax < 3; ++ax) {
      const int b1 = ax == 0 ? 1 : 0, b2 = ax == 2 ? 1 : 2;
      for (int side = 0; side < 2; ++side)
        for (int r = 0; r < 4; ++r)
          for (int q = 0; q < 8; ++q)
            if (cpdi::cornerSign<3>(q, ax) == (side ? 1.0 : -1.0) &&
                cpdi::cornerSign<3>(q, b1) == s1[r] && cpdi::cornerSign<3>(q, b2) == s2[r])
              t[ax][side][r] = q;
    }
    return t;
  }();
  return table[a][n > 0].data();
}

/// The tent of slot s's node across the face normal to axis a at coordinate `at` (Eq. 14).
template <int D> inline double tentAcross(const Grid<D> &g, PetscInt s, int a, double at) {
  const PetscInt nd = g.slotNode[s];
  return shape::tent(at - g.coordinates(a)[nd], g.zone[2 * D * nd + 2 * a],
                     g.zone[2 * D * nd + 2 * a + 1]);
}

/// S_i of stencil entry e integrated over the particle face normal to axis a on side n = +-1,
/// lying at coordinate `at`, per unit area: the tent across times the 1D weights along. With
/// CPDI stencils the face is the edge (2D) or quadrilateral (3D) of the particle's corners on
/// that side and S_i bi/linear over it (the corners' N_i averaged).
template <int D>
inline double faceShape(const Grid<D> &g, const Stencils<D> &st, PetscInt e, int a, double n,
                        double at) {
  if (st.general) {
    if constexpr (D == 2) {
      int c1, c2;
      edgeCorners(a, n, c1, c2);
      return 0.5 * (st.cw[4 * e + c1] + st.cw[4 * e + c2]);
    } else {
      const int *c = faceCorners(a, n);
      return 0.25 * (st.cw[8 * e + c[0]] + st.cw[8 * e + c[1]] + st.cw[8 * e + c[2]] +
                     st.cw[8 * e + c[3]]);
    }
  }
  double w = tentAcross(g, st.node[e], a, at);
  for (int d = 0; d < D; ++d)
    if (d != a) w *= st.w[d][e];
  return w;
}

/// Spread a force acting on particle k's face normal to axis a on side n at `at` onto fe.
template <int D>
inline void spreadFaceForce(const Grid<D> &g, const Stencils<D> &st, PetscInt k, int a, double n,
                            double at, const double force[D], double *fe) {
  // A block: the same shape from its 1D factors (regular nodes, no cracks), over the nodes
  // forEach visits; the node's index along each axis from its offset in the block.
  auto block = [&](const auto &b) {
    st.forEach(k, [&](PetscInt nd, double, const Vector<D> &) {
      PetscInt off = nd - b.base, idx[D];
      for (int d = D - 1; d > 0; --d) {
        idx[d] = off / b.stride[d - 1];
        off -= idx[d] * b.stride[d - 1];
      }
      idx[0] = off;
      double w = tentAcross(g, nd, a, at);
      for (int d = 0; d < D; ++d)
        if (d != a) w *= b.w[d][idx[d]];
      for (int c = 0; c < D; ++c)
        fe[D * nd + c] += w * force[c];
    });
  };
  if (st.isBlock(k)) return block(st.block(k));
  if constexpr (D == 2)
    if (st.isBlock4(k)) return block(st.block4(k));
  if (st.isLevels(k)) { // faceShape's product from the entries' 1D factors
    typename Stencils<D>::LevelRow r;
    for (auto rows = st.levelRows(k); rows.next(r);)
      for (int i = 0; i < 4; ++i) {
        if (!((r.nodes >> i) & 1u)) continue;
        const PetscInt nd = r.slot + i;
        const double fw[3] = {r.w0[i], r.block->w[1][r.j], D == 3 ? r.block->w[D - 1][r.q] : 0.0};
        double w = tentAcross(g, nd, a, at);
        for (int d = 0; d < D; ++d)
          if (d != a) w *= fw[d];
        for (int c = 0; c < D; ++c)
          fe[D * nd + c] += w * force[c];
      }
    return;
  }
  for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e) {
    const double w = faceShape(g, st, e, a, n, at);
    for (int c = 0; c < D; ++c)
      fe[D * st.node[e] + c] += w * force[c];
  }
}

template <int D> class Boundary {
public:
  /// The penalty alpha of Eq. 9 from -gimp_penalty or chosen from the material, grid and dt,
  /// checked against its stability bounds (the same on every rank). Prints it. With
  /// `constantBounds` false the bounds are left to the eigenvalue check (stability room).
  PetscErrorCode setup(MPI_Comm comm, const Scene<D> &sc, const Lattice<D> &grid, double dt,
                       bool constantBounds = true);

  /// The change of the penalty forces of Eq. 9 (springs and, when the scene has it, the traction
  /// term) into fe: the face moves by du_p (du, a window array, interpolated at the particle) plus
  /// the change of F, L F n l0 (L row-major D x D per particle); the stress changes by ds. A null
  /// input leaves its part out; `springs` false leaves the springs out. Faces and areas stay
  /// those of the current configuration.
  void penaltyIncrement(const Scene<D> &sc, const Grid<D> &g, const Stencils<D> &st,
                        const ParticleView<D> &p, const double *du, const double *L,
                        const double *ds, bool springs, double *fe) const;

  /// Whether the scene has external nodal forces (body force, tractions, penalty terms).
  bool active() const { return active_; }

  /// External nodal forces at time t accumulated into the window array fe; records each penalty
  /// condition's force on the body and its largest violation on this rank. With `scale`, each
  /// particle's body force and tractions are multiplied by its factor (a multi-rate particle's
  /// first kick in a new rate class).
  void externalForces(const Scene<D> &sc, const Grid<D> &g, const Stencils<D> &st,
                      const ParticleView<D> &p, double t, double *fe,
                      const double *scale = nullptr);

  /// Each penalty condition's force (D components) summed over ranks and its largest violation
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
  void penaltyForces(const Scene<D> &sc, const Grid<D> &g, const Stencils<D> &st,
                     const ParticleView<D> &p, double t, double *fe);

  bool active_ = false;
  double alpha_ = 0;              // penalty of Eq. 9 in use [Pa/m]
  std::vector<double> reactions_; // this rank's part of each condition's force (D components)
  std::vector<double> gaps_;      // this rank's largest |u - u_bar| per condition
  std::vector<double> maxGap_;    // largest violation per condition over the reports
};

extern template class Boundary<2>;
extern template class Boundary<3>;

} // namespace gimp::physics
