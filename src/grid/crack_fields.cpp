// Second velocity fields at the nodes a crack cuts (explicit cracks): which nodes, who owns
// their second field in the composite Vec that TS advances, and their window slots.
//
// A node needs a second field when a particle-to-node segment may cross a crack: the crack comes
// within a particle's reach (h0, the largest half-size the checks allow) of the node's support
// [X - Lx-, X + Lx+] x [Y - Ly-, Y + Ly+] (x [Z - Lz-, Z + Lz+]). The set depends only on the
// geometry, so every rank finds the same list in the same order, and memory grows with the
// crack's length (2D) or area (3D), not the grid. Where a crack may grow (Grid::crackReserve,
// Grid::crackReserveSurfaces), every node within the reach of that disk or polygon gets one too,
// at setup. The second field of a cracked
// node is owned by the rank owning the node's level-0 cell and is stored in a DMShell appended to
// the levels' DMComposite.
#include "gimp/grid/crack_fields.hpp"

#include <petscdmshell.h>

#include <algorithm>
#include <cmath>

namespace gimp {

namespace {

/// Bounding boxes (low corner, then high corner) of the pieces of a crack that the node search
/// visits one at a time: a polyline's segments, a polygon as a whole.
std::vector<std::array<double, 4>> pieces(const Crack &c) {
  std::vector<std::array<double, 4>> out;
  for (size_t s = 0; s + 1 < c.points.size(); ++s) {
    const auto &p = c.points[s], &q = c.points[s + 1];
    out.push_back(
        {std::min(p[0], q[0]), std::min(p[1], q[1]), std::max(p[0], q[0]), std::max(p[1], q[1])});
  }
  return out;
}
std::vector<std::array<double, 6>> pieces(const CrackSurface &c) {
  return {cracks::bounds<3>(c)};
}

} // namespace

template <int D>
std::vector<typename Grid<D>::CrackedNode>
Grid<D>::findCrackedNodes(const std::vector<CrackOf<D>> &cracks) const {
  std::vector<CrackedNode> out;
  // A particle (half-size at most h0) whose domain meets a node's support has its centre within
  // the support widened by h0 along each axis: at most sqrt(D) h0 from the support. The reach of
  // markLiveCracks for that size, with its allowance for crossing()'s tolerance (span: the
  // crack's extent along the axes), so that every node it marks live has a second field.
  const double root = std::sqrt(static_cast<double>(D));
  const auto reachOf = [&](double span) { return root * this->h0() * (1 + 1e-6) + 1e-6 * span; };
  // Visits the active nodes of level k whose support may meet the box [lo, hi] widened by w,
  // with their support [X - z-, X + z+] along each axis (lows, then highs).
  const auto nodesNear = [&](int k, const double *lo, const double *hi, double w, auto &&visit) {
    const Level<D> &L = levels[k];
    Index i0{};
    std::array<PetscInt, D> n{};
    for (int a = 0; a < D; ++a) {
      i0[a] = std::max<std::int64_t>(0, std::floor((lo[a] - w - L.box[a]) * L.ih));
      const std::int64_t i1 =
          std::min<std::int64_t>(L.n[a] - 1, std::ceil((hi[a] + w - L.box[a]) * L.ih));
      n[a] = static_cast<PetscInt>(i1 - i0[a] + 1);
    }
    forEachIndex<D>(n, [&](const Index &d) {
      Index i{};
      for (int a = 0; a < D; ++a)
        i[a] = i0[a] + d[a];
      if (!this->nodeActive(k, i)) return;
      double z[2 * D], support[2 * D];
      this->zonesOf(k, i, z);
      for (int a = 0; a < D; ++a) {
        const double X = this->nodeCoordinate(k, a, i[a]);
        support[a] = X - z[2 * a];
        support[D + a] = X + z[2 * a + 1];
      }
      visit(i, support);
    });
  };
  for (int k = 0; k < static_cast<int>(levels.size()); ++k)
    for (const auto *list : {&cracks, &crackReserveSurfaces})
      for (const CrackOf<D> &c : *list) {
        const std::array<double, 2 *D> b = cracks::bounds<D>(c);
        double span = 0;
        for (int a = 0; a < D; ++a)
          span += b[D + a] - b[a];
        const double reach = reachOf(span);
        for (const auto &piece : pieces(c)) // nodes whose support, widened by the reach, meets it
          nodesNear(k, piece.data(), piece.data() + D, reach + this->h0(),
                    [&](const Index &i, const double *support) {
                      if (cracks::nearCrack(c, support, reach)) out.push_back({k, i, 0, 0});
                    });
      }
  // The nodes where a crack may grow: support, widened by the reach, within the disk's radius
  // of its centre.
  for (int k = 0; k < static_cast<int>(levels.size()); ++k)
    for (const std::array<double, D + 1> &disk : crackReserve) {
      const double reach = reachOf(2 * D * disk[D]);
      nodesNear(
          k, disk.data(), disk.data(), disk[D] + reach + this->h0(),
          [&](const Index &i, const double *support) {
            double gap2 = 0;
            for (int a = 0; a < D; ++a) {
              const double g = std::max({0.0, support[a] - disk[a], disk[a] - support[D + a]});
              gap2 += g * g;
            }
            if (std::sqrt(gap2) <= disk[D] + reach) out.push_back({k, i, 0, 0});
          });
    }
  // Level, then the index with its last axis slowest (the levels' node order).
  const auto key = [](const CrackedNode &a) {
    std::array<std::int64_t, D + 1> r{};
    r[0] = a.k;
    for (int d = 0; d < D; ++d)
      r[1 + d] = a.i[D - 1 - d];
    return r;
  };
  std::sort(out.begin(), out.end(),
            [&](const CrackedNode &a, const CrackedNode &b) { return key(a) < key(b); });
  out.erase(std::unique(out.begin(), out.end(),
                        [](const CrackedNode &a, const CrackedNode &b) {
                          return a.k == b.k && a.i == b.i;
                        }),
            out.end());
  return out;
}

template <int D>
PetscErrorCode Grid<D>::addCrackFields(MPI_Comm comm, const std::vector<CrackOf<D>> &cracks) {
  // The window's own slots are set (GridT::build); the second fields come after them.
  patterns_.forget();
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (cracks.empty()) return PETSC_SUCCESS;
  cracked_ = findCrackedNodes(cracks);
  for (CrackedNode &c : cracked_) {
    // The rank owning the level-0 cell whose lower corner is at or before the node.
    double x[D];
    for (int a = 0; a < D; ++a)
      x[a] = this->nodeCoordinate(c.k, a, c.i[a]) + 0.25 * unit;
    c.owner = ownerOf(x);
    c.ownerPos = crackCount_[c.owner]++;
  }
  for (size_t g = 0; g < cracked_.size(); ++g) {
    const CrackedNode &c = cracked_[g];
    const Level<D> &L = levels[c.k];
    PetscInt ij[D];
    bool inWindow = true;
    for (int a = 0; a < D; ++a) {
      ij[a] = static_cast<PetscInt>(c.i[a]);
      inWindow = inWindow && ij[a] >= L.w0[a] && ij[a] < L.w1[a];
    }
    if (!inWindow) continue;
    const PetscInt n = windowSlot(c.k, ij);
    crackSlot[n] = nSlots++;
    slotNode.push_back(n);
    crackedOfSlot_.push_back(static_cast<PetscInt>(g));
  }
  if (cracked_.empty()) return PETSC_SUCCESS;
  Vec g, l;
  PetscCall(DMShellCreate(comm, &crackDm));
  PetscCall(VecCreateMPI(comm, D * crackCount_[rank], PETSC_DETERMINE, &g));
  PetscCall(VecSetBlockSize(g, D));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, D * crackCount_[rank], &l));
  PetscCall(VecSetBlockSize(l, D));
  PetscCall(DMShellSetGlobalVector(crackDm, g));
  PetscCall(DMShellSetLocalVector(crackDm, l));
  PetscCall(VecDestroy(&g));
  PetscCall(VecDestroy(&l));
  PetscCall(DMCompositeAddDM(dm, crackDm));
  return PETSC_SUCCESS;
}

template <int D> double Grid<D>::liveReachFor(double lmax) const {
  double r = this->h0();
  for (int k = 0; k < 40 && 0.5 * r >= lmax; ++k)
    r *= 0.5;
  return r;
}

template <int D> void Grid<D>::markLiveCracks(const std::vector<CrackOf<D>> &cracks, double reach) {
  patterns_.forget();
  liveSlot.clear();
  crackFreeThree_.clear();
  crackFreeFour_.clear();
  liveReach_ = reach;
  if (nSlots == nWindow) return; // no cracked node in this window
  // A particle whose domain meets node n's support has its centre within the support widened by
  // its half-size along each axis, at most sqrt(D) reach from the support; a segment from there
  // to the node that crosses a crack puts the crack that near the support. crossing() counts a
  // crack within its tolerance, kCrackTol (1e-9) of the segment's and the crack's sizes, of the
  // segment: a millionth of the reach and of the crack's size covers it. (findCrackedNodes asks
  // the same of the cracks and the growth reserve, for particles up to h0.)
  std::vector<double> near;
  for (const CrackOf<D> &c : cracks) {
    const std::array<double, 2 *D> b = cracks::bounds<D>(c);
    double span = 0;
    for (int a = 0; a < D; ++a)
      span += b[D + a] - b[a];
    near.push_back(std::sqrt(static_cast<double>(D)) * reach * (1 + 1e-6) + 1e-6 * span);
  }
  // The blocks of the compact path: the regular ones, less every block that holds a marked node
  // (block origins from side - 1 nodes before it to it along each axis).
  crackFreeThree_ = threeNodeBlocks_;
  crackFreeFour_ = fourNodeBlocks_;
  const auto clear = [&](int k, const PetscInt *i, PetscInt side, std::vector<std::uint8_t> &flag) {
    const Level<D> &L = levels[k];
    std::array<PetscInt, D> back;
    back.fill(side);
    forEachIndex<D>(back, [&](const Index &b) {
      PetscInt j[D];
      for (int a = 0; a < D; ++a) {
        j[a] = i[a] - b[a];
        if (j[a] < L.w0[a]) return;
      }
      flag[windowSlot(k, j)] = 0;
    });
  };
  liveSlot.assign(nWindow, -1);
  for (PetscInt s = nWindow; s < nSlots; ++s) {
    const PetscInt n = slotNode[s];
    double support[2 * D];
    for (int a = 0; a < D; ++a) {
      const double X = coordinates(a)[n];
      support[a] = X - zone[2 * D * n + 2 * a];
      support[D + a] = X + zone[2 * D * n + 2 * a + 1];
    }
    for (size_t q = 0; q < cracks.size(); ++q)
      if (cracks::nearCrack(cracks[q], support, near[q])) {
        liveSlot[n] = s;
        const CrackedNode &c = cracked_[crackedOfSlot_[s - nWindow]];
        PetscInt i[D];
        for (int a = 0; a < D; ++a)
          i[a] = static_cast<PetscInt>(c.i[a]);
        clear(c.k, i, 3, crackFreeThree_);
        if (D == 2) clear(c.k, i, 4, crackFreeFour_);
        break;
      }
  }
}

template void Grid<2>::markLiveCracks(const std::vector<CrackOf<2>> &, double);
template void Grid<3>::markLiveCracks(const std::vector<CrackOf<3>> &, double);
template double Grid<2>::liveReachFor(double) const;
template double Grid<3>::liveReachFor(double) const;
template std::vector<Grid<2>::CrackedNode>
Grid<2>::findCrackedNodes(const std::vector<CrackOf<2>> &) const;
template std::vector<Grid<3>::CrackedNode>
Grid<3>::findCrackedNodes(const std::vector<CrackOf<3>> &) const;
template PetscErrorCode Grid<2>::addCrackFields(MPI_Comm, const std::vector<CrackOf<2>> &);
template PetscErrorCode Grid<3>::addCrackFields(MPI_Comm, const std::vector<CrackOf<3>> &);

namespace cracks {

template <int D>
void assignFields(const Grid<D> &g, const std::vector<CrackOf<D>> &cracks, PetscInt n,
                  const double *x, Stencils<D> &st) {
  if (g.nSlots == g.nWindow) return; // no cracked node in this window
  PetscInt *node = st.node.data();
  if constexpr (D == 2) {
    // Per particle, the segments of each crack near the box of its centre and its live nodes:
    // crossing() asks those alone (segmentsNear), a polyline that grew long stays cheap.
    std::vector<std::vector<int>> near(cracks.size());
    for (PetscInt k = 0; k < n; ++k) {
      double box[4] = {x[2 * k], x[2 * k + 1], x[2 * k], x[2 * k + 1]};
      bool live = false;
      for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e) {
        if (g.liveSlot[node[e]] < 0) continue;
        live = true;
        const double X = g.X[node[e]], Y = g.Y[node[e]];
        box[0] = std::min(box[0], X);
        box[1] = std::min(box[1], Y);
        box[2] = std::max(box[2], X);
        box[3] = std::max(box[3], Y);
      }
      if (!live) continue;
      for (size_t q = 0; q < cracks.size(); ++q)
        segmentsNear(cracks[q], box, near[q]);
      for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e) {
        const PetscInt second = g.liveSlot[node[e]];
        if (second < 0) continue;
        for (size_t q = 0; q < cracks.size(); ++q)
          if (!near[q].empty() && crossing(cracks[q], near[q], x[2 * k], x[2 * k + 1], g.X[node[e]],
                                           g.Y[node[e]]) != 0) {
            node[e] = second;
            break;
          }
      }
    }
    return;
  }
  for (PetscInt k = 0; k < n; ++k)
    for (PetscInt e = st.start[k]; e < st.start[k + 1]; ++e) {
      const PetscInt second = g.liveSlot[node[e]];
      if (second < 0) continue; // (no crack within reach: crossing() is 0 for every crack)
      double X[D];
      for (int a = 0; a < D; ++a)
        X[a] = g.coordinates(a)[node[e]];
      for (const CrackOf<D> &c : cracks)
        if (crossing(c, &x[D * k], X) != 0) {
          node[e] = second;
          break;
        }
    }
}

template void assignFields(const Grid<2> &, const std::vector<CrackOf<2>> &, PetscInt,
                           const double *, Stencils<2> &);
template void assignFields(const Grid<3> &, const std::vector<CrackOf<3>> &, PetscInt,
                           const double *, Stencils<3> &);

} // namespace cracks

} // namespace gimp
