// Second velocity fields at the nodes a crack cuts (explicit cracks): which nodes, who owns
// their second field in the composite Vec that TS advances, and their window slots.
//
// A node needs a second field when a particle-to-node segment may cross a crack: the crack comes
// within a particle's reach (h0, the largest half-size the checks allow) of the node's support
// [X - Lx-, X + Lx+] x [Y - Ly-, Y + Ly+]. The set depends only on the geometry, so every rank
// finds the same list in the same order, and memory grows with the crack length, not the grid.
// The second field of a cracked node is owned by the rank owning the node's level-0 cell and is
// stored in a DMShell appended to the levels' DMComposite.
#include "gimp/grid/crack_fields.hpp"

#include <petscdmshell.h>

#include <algorithm>
#include <cmath>
#include <tuple>

namespace gimp {

template <>
std::vector<Grid<2>::CrackedNode>
Grid<2>::findCrackedNodes(const std::vector<Crack> &cracks) const {
  std::vector<CrackedNode> out;
  const double reach = h0();
  for (int k = 0; k < static_cast<int>(levels.size()); ++k) {
    const Level<2> &L = levels[k];
    for (const Crack &c : cracks)
      for (size_t s = 0; s + 1 < c.points.size(); ++s) {
        // Nodes of level k whose support, widened by the reach, may meet this segment.
        const double w = reach + h0();
        const double lox = std::min(c.points[s][0], c.points[s + 1][0]) - w,
                     hix = std::max(c.points[s][0], c.points[s + 1][0]) + w,
                     loy = std::min(c.points[s][1], c.points[s + 1][1]) - w,
                     hiy = std::max(c.points[s][1], c.points[s + 1][1]) + w;
        const PetscInt i0 = std::max<PetscInt>(0, std::floor((lox - L.box[0]) * L.ih)),
                       i1 = std::min<PetscInt>(L.n[0] - 1, std::ceil((hix - L.box[0]) * L.ih)),
                       j0 = std::max<PetscInt>(0, std::floor((loy - L.box[1]) * L.ih)),
                       j1 = std::min<PetscInt>(L.n[1] - 1, std::ceil((hiy - L.box[1]) * L.ih));
        for (PetscInt j = j0; j <= j1; ++j)
          for (PetscInt i = i0; i <= i1; ++i) {
            if (!nodeActive(k, {i, j})) continue;
            double z[4];
            zonesOf(k, {i, j}, z);
            const double X = nodeCoordinate(k, 0, i), Y = nodeCoordinate(k, 1, j);
            const double support[4] = {X - z[0], Y - z[2], X + z[1], Y + z[3]};
            if (cracks::nearCrack(c, support, reach)) out.push_back({k, i, j, 0, 0});
          }
      }
  }
  std::sort(out.begin(), out.end(), [](const CrackedNode &a, const CrackedNode &b) {
    return std::tie(a.k, a.j, a.i) < std::tie(b.k, b.j, b.i);
  });
  out.erase(std::unique(out.begin(), out.end(),
                        [](const CrackedNode &a, const CrackedNode &b) {
                          return a.k == b.k && a.i == b.i && a.j == b.j;
                        }),
            out.end());
  return out;
}

template <>
PetscErrorCode Grid<2>::addCrackFields(MPI_Comm comm, const std::vector<Crack> &cracks) {
  // The window's own slots are set (GridT::build); the second fields come after them.
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (cracks.empty()) return PETSC_SUCCESS;
  cracked_ = findCrackedNodes(cracks);
  for (CrackedNode &c : cracked_) {
    // The rank owning the level-0 cell whose lower-left corner is at or before the node.
    const double X = nodeCoordinate(c.k, 0, c.i), Y = nodeCoordinate(c.k, 1, c.j);
    c.owner = ownerOf(X + 0.25 * unit, Y + 0.25 * unit);
    c.ownerPos = crackCount_[c.owner]++;
  }
  for (size_t g = 0; g < cracked_.size(); ++g) {
    const CrackedNode &c = cracked_[g];
    const Level<2> &L = levels[c.k];
    if (c.i < L.w0[0] || c.i >= L.w1[0] || c.j < L.w0[1] || c.j >= L.w1[1]) continue;
    const PetscInt ij[2] = {c.i, c.j};
    const PetscInt n = windowSlot(c.k, ij);
    crackSlot[n] = nSlots++;
    slotNode.push_back(n);
    crackedOfSlot_.push_back(static_cast<PetscInt>(g));
  }
  if (cracked_.empty()) return PETSC_SUCCESS;
  Vec g, l;
  PetscCall(DMShellCreate(comm, &crackDm));
  PetscCall(VecCreateMPI(comm, 2 * crackCount_[rank], PETSC_DETERMINE, &g));
  PetscCall(VecSetBlockSize(g, 2));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, 2 * crackCount_[rank], &l));
  PetscCall(VecSetBlockSize(l, 2));
  PetscCall(DMShellSetGlobalVector(crackDm, g));
  PetscCall(DMShellSetLocalVector(crackDm, l));
  PetscCall(VecDestroy(&g));
  PetscCall(VecDestroy(&l));
  PetscCall(DMCompositeAddDM(dm, crackDm));
  return PETSC_SUCCESS;
}

namespace cracks {

void assignFields(const Grid<2> &g, const std::vector<Crack> &cracks, PetscInt n, const double *x,
                  Stencils<2> &st) {
  if (g.nSlots == g.nWindow) return; // no cracked node in this window
  PetscInt *node = st.node.data();
  for (PetscInt k = 0; k < n; ++k)
    for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e) {
      const PetscInt second = g.crackSlot[node[e]];
      if (second < 0) continue;
      for (const Crack &c : cracks)
        if (crossing(c, x[2 * k], x[2 * k + 1], g.X[node[e]], g.Y[node[e]]) != 0) {
          node[e] = second;
          break;
        }
    }
}

} // namespace cracks

} // namespace gimp
